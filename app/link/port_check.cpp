#include "app/link/port_check.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "app/link/port_openers.hpp"

namespace nlsoft::console {

namespace {

// /proc/locks rows: "1: FLOCK  ADVISORY  WRITE 4242 00:05:17 0 EOF", the
// device as hex major:minor and the inode in decimal.
std::string lock_holder(int fd) {
  struct stat st {};
  if (fstat(fd, &st) != 0) return "";
  std::ifstream locks("/proc/locks");
  std::string line;
  while (std::getline(locks, line)) {
    std::istringstream in(line);
    std::string id, kind, mode, access, pid, dev_ino;
    if (!(in >> id >> kind)) continue;
    if (kind == "->") in >> kind;  // a blocked waiter
    if (!(in >> mode >> access >> pid >> dev_ino) || kind != "FLOCK") continue;
    unsigned major_ = 0, minor_ = 0;
    unsigned long inode = 0;
    if (std::sscanf(dev_ino.c_str(), "%x:%x:%lu", &major_, &minor_, &inode) != 3) continue;
    if (inode != st.st_ino || major_ != major(st.st_dev) || minor_ != minor(st.st_dev)) continue;
    if (std::to_string(getpid()) == pid) continue;
    std::ifstream comm("/proc/" + pid + "/comm");
    std::string name;
    std::getline(comm, name);
    return name.empty() ? "PID " + pid : fmt::format("PID {} ({})", pid, name);
  }
  return "";
}

}  // namespace

std::string check_terminal(int fd, const std::string& path) {
  struct stat dev {};
  // /dev/ptmx (5:2) opens a new pseudo-terminal each time, with nothing at
  // its other end: a console on it would wait for a firmware that cannot be there.
  if (fd >= 0 && fstat(fd, &dev) == 0 && S_ISCHR(dev.st_mode) && major(dev.st_rdev) == 5 && minor(dev.st_rdev) == 2)
    return fmt::format("not a serial port: {} makes a new pseudo-terminal at each open, with nothing at its other "
                       "end; give the /dev/pts/N a simulator printed (nlsoft-firmware-sim prints it)",
                       path);
  if (fd >= 0 && isatty(fd)) return "";
  struct stat st {};
  const char* what = "not a terminal";
  if (fd >= 0 ? fstat(fd, &st) == 0 : stat(path.c_str(), &st) == 0) {
    if (S_ISREG(st.st_mode)) what = "a regular file";
    else if (S_ISDIR(st.st_mode)) what = "a directory";
    else if (S_ISSOCK(st.st_mode)) what = "a socket";
    else if (S_ISFIFO(st.st_mode)) what = "a pipe";
    else if (S_ISCHR(st.st_mode)) what = "a character device that is not a terminal";
  }
  return fmt::format("not a serial port: {} is {}", path, what);
}

std::string take_exclusive(int fd, const std::string& path) {
  if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno != EWOULDBLOCK) return "";  // no locking on this file system: nothing to enforce
    const std::string holder = lock_holder(fd);
    return holder.empty() ? fmt::format("port busy: {} is held by another program", path)
                          : fmt::format("port busy: {} is held by {}", path, holder);
  }
  ioctl(fd, TIOCEXCL);  // best effort: a pty master may refuse it
  return "";
}

std::string check_no_other_reader(int fd, const std::string& path) {
  const std::vector<PortOpener> others = other_openers(fd);
  if (others.empty()) return "";
  return fmt::format("port busy: {} is also open in {}, which would read the replies meant for this console; "
                     "end {} first",
                     path, describe_openers(others), others.size() == 1 ? "it" : "them");
}

bool is_pseudo_terminal(int fd) {
  struct stat st {};
  if (fstat(fd, &st) != 0 || !S_ISCHR(st.st_mode)) return false;
  const unsigned m = major(st.st_rdev);
  return m >= 136 && m <= 143;  // UNIX98 pty slaves (Documentation/admin-guide/devices.txt)
}

}  // namespace nlsoft::console
