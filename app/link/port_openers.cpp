#include "app/link/port_openers.hpp"

#include <dirent.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>

namespace nlsoft::console {

namespace {

std::vector<pid_t> pids() {
  std::vector<pid_t> out;
  DIR* d = ::opendir("/proc");
  if (!d) return out;
  while (const dirent* e = ::readdir(d)) {
    char* end = nullptr;
    const long pid = std::strtol(e->d_name, &end, 10);
    if (end != e->d_name && *end == '\0' && pid > 0) out.push_back(pid_t(pid));
  }
  ::closedir(d);
  std::sort(out.begin(), out.end());
  return out;
}

// Calls f(fd name, stat of what it leads to) for each open file of pid.
template <class F>
void for_each_fd(pid_t pid, F f) {
  const std::string dir = fmt::format("/proc/{}/fd", pid);
  DIR* d = ::opendir(dir.c_str());
  if (!d) return;  // gone, or another user's
  while (const dirent* e = ::readdir(d)) {
    if (e->d_name[0] == '.') continue;
    struct stat st {};
    if (::stat((dir + "/" + e->d_name).c_str(), &st) == 0) f(std::string(e->d_name), st);
  }
  ::closedir(d);
}

// /proc/PID/fdinfo/FD of a pty master names the pty it leads to:
// "tty-index:\t5" for /dev/pts/5.
int tty_index(pid_t pid, const std::string& fd) {
  std::ifstream in(fmt::format("/proc/{}/fdinfo/{}", pid, fd));
  for (std::string line; std::getline(in, line);)
    if (line.rfind("tty-index:", 0) == 0) return std::atoi(line.c_str() + 10);
  return -1;
}

std::string command_of(pid_t pid) {
  std::ifstream comm(fmt::format("/proc/{}/comm", pid));
  std::string name;
  std::getline(comm, name);
  return name;
}

// UNIX98 pty slaves (Documentation/admin-guide/devices.txt) and the master
// multiplexer, /dev/ptmx (5:2).
bool is_pty_slave(dev_t d) { return major(d) >= 136 && major(d) <= 143; }
bool is_pty_master(const struct stat& st) { return S_ISCHR(st.st_mode) && major(st.st_rdev) == 5 && minor(st.st_rdev) == 2; }

}  // namespace

std::vector<PortOpener> other_openers(int fd) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) return {};
  return other_openers(st);
}

std::vector<PortOpener> other_openers(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return {};
  return other_openers(st);
}

std::vector<PortOpener> other_openers(const struct stat& mine) {
  if (!S_ISCHR(mine.st_mode)) return {};
  // Every open of /dev/ptmx is a pty of its own: other masters are other lines.
  if (is_pty_master(mine)) return {};
  const dev_t dev = mine.st_rdev;
  // A slave's number: (major - 136) * 256 + minor.
  const int index = is_pty_slave(dev) ? int((major(dev) - 136) * 256 + minor(dev)) : -1;
  const pid_t self = ::getpid();
  std::vector<PortOpener> out;
  for (const pid_t pid : pids()) {
    if (pid == self) continue;
    bool opens = false, other_end = false;
    for_each_fd(pid, [&](const std::string& name, const struct stat& st) {
      if (S_ISCHR(st.st_mode) && st.st_rdev == dev) opens = true;
      if (index >= 0 && is_pty_master(st) && tty_index(pid, name) == index) other_end = true;
    });
    if (opens && !other_end) out.push_back({pid, command_of(pid)});
  }
  return out;
}

std::string also_open_words(const std::vector<PortOpener>& openers, const std::string& port) {
  return fmt::format("{} also {} {} open", describe_openers(openers), openers.size() == 1 ? "has" : "have", port);
}

std::string describe_openers(const std::vector<PortOpener>& openers) {
  std::string s;
  for (size_t i = 0; i < openers.size(); ++i) {
    const PortOpener& o = openers[i];
    s += i == 0 ? "" : i + 1 == openers.size() ? " and " : ", ";
    s += o.command.empty() ? fmt::format("PID {}", o.pid) : fmt::format("PID {} ({})", o.pid, o.command);
  }
  return s;
}

}  // namespace nlsoft::console
