#include "host/files/output_file.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <optional>

#include "host/files/cli_error.hpp"

namespace nlsoft::host {

namespace {

// Links followed before giving up, as the kernel's own limit (ELOOP).
constexpr int kMaxLinks = 40;

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw CliError(fmt::format("cannot write {}: {}", path, why));
}

bool all_digits(const std::string& s) {
  return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
}

struct ProcFd {
  bool ours = false;
  int fd = -1;
};

// "/proc/PID/fd/N" or "/proc/PID/task/TID/fd/N" (what /dev/stdout, /dev/fd/N
// and /proc/self/fd/N come to once their directories are resolved). Such a
// name is a kernel handle on a descriptor, not a file: renaming over it is
// meaningless, and reading the link gives "pipe:[…]" or a path the
// descriptor may no longer be at.
std::optional<ProcFd> proc_fd(const std::string& full) {
  if (full.rfind("/proc/", 0) != 0) return std::nullopt;
  std::string rest = full.substr(6);
  const size_t a = rest.find('/');
  if (a == std::string::npos) return std::nullopt;
  const std::string pid = rest.substr(0, a);
  rest = rest.substr(a + 1);
  if (rest.rfind("task/", 0) == 0) {
    const size_t b = rest.find('/', 5);
    if (b == std::string::npos || !all_digits(rest.substr(5, b - 5))) return std::nullopt;
    rest = rest.substr(b + 1);
  }
  if (!all_digits(pid) || rest.rfind("fd/", 0) != 0 || !all_digits(rest.substr(3))) return std::nullopt;
  ProcFd p;
  p.ours = std::strtol(pid.c_str(), nullptr, 10) == long(::getpid());
  p.fd = int(std::strtol(rest.substr(3).c_str(), nullptr, 10));
  return p;
}

}  // namespace

OutputTarget output_target(const std::string& path) {
  if (path == "-") return {OutputTarget::Stdout, "-", 1};
  if (path.empty()) throw CliError("cannot write a file with an empty name");
  // Resolved one link at a time rather than with realpath(): realpath()
  // needs the last component to exist and resolves /dev/stdout to whatever
  // the descriptor points at, losing that it was a descriptor.
  std::string cur = path;
  for (int hops = 0; hops <= kMaxLinks; ++hops) {
    const size_t slash = cur.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : cur.substr(0, slash);
    const std::string base = slash == std::string::npos ? cur : cur.substr(slash + 1);
    if (base.empty() || base == "." || base == "..") fail(path, "it is a directory");
    char real_dir[PATH_MAX];
    if (!::realpath(dir.c_str(), real_dir)) fail(path, std::strerror(errno));
    const std::string full = (std::string(real_dir) == "/" ? "" : std::string(real_dir)) + "/" + base;
    if (const auto p = proc_fd(full)) {
      if (p->ours) return {OutputTarget::Descriptor, full, p->fd};
      return {OutputTarget::InPlace, full, -1};
    }
    struct stat st {};
    if (::lstat(full.c_str(), &st) != 0) {
      if (errno == ENOENT) return {OutputTarget::Replace, full, -1};
      fail(path, std::strerror(errno));
    }
    if (S_ISLNK(st.st_mode)) {
      char target[PATH_MAX];
      const ssize_t n = ::readlink(full.c_str(), target, sizeof target - 1);
      if (n < 0) fail(path, std::strerror(errno));
      target[n] = '\0';
      cur = target[0] == '/' ? std::string(target) : std::string(real_dir) + "/" + target;
      continue;
    }
    if (S_ISDIR(st.st_mode)) fail(path, "it is a directory");
    if (S_ISREG(st.st_mode)) return {OutputTarget::Replace, full, -1};
    return {OutputTarget::InPlace, full, -1};  // a device, FIFO or socket
  }
  fail(path, std::strerror(ELOOP));
}

OutputFile::OutputFile(const std::string& path) : path_(path) {
  const OutputTarget t = output_target(path);
  real_ = t.path;
  switch (t.kind) {
    case OutputTarget::Stdout:
      f_ = stdout;
      stdout_ = true;
      return;
    case OutputTarget::Descriptor: {
      // What this process already wrote to the descriptor goes first.
      std::fflush(stdout);
      std::fflush(stderr);
      const int fd = ::dup(t.fd);
      if (fd < 0) fail(path, std::strerror(errno));
      f_ = ::fdopen(fd, "w");  // no truncation: `>>` appends, `>` was truncated by the shell
      if (!f_) {
        const int e = errno;
        ::close(fd);
        fail(path, std::strerror(e));
      }
      return;
    }
    case OutputTarget::InPlace:
      f_ = std::fopen(real_.c_str(), "w");
      if (!f_) fail(path, std::strerror(errno));
      return;
    case OutputTarget::Replace:
      break;
  }
  // mkstemp beside the real path: same file system, so the rename is atomic
  std::string tmpl = real_ + ".XXXXXX";
  const int fd = ::mkstemp(tmpl.data());
  if (fd < 0) fail(path, std::strerror(errno));
  // The replaced file keeps its mode and owner; a new one is 0644.
  struct stat old {};
  if (::stat(real_.c_str(), &old) == 0) {
    ::fchmod(fd, old.st_mode & 07777);
    if (::fchown(fd, old.st_uid, old.st_gid) != 0) {
      // not root: the file becomes ours, as any editor's save would make it
    }
  } else {
    ::fchmod(fd, 0644);
  }
  f_ = ::fdopen(fd, "w");
  if (!f_) {
    const int e = errno;
    ::close(fd);
    ::unlink(tmpl.c_str());
    fail(path, std::strerror(e));
  }
  tmp_ = tmpl;
}

OutputFile::~OutputFile() {
  if (!f_ || stdout_) return;
  std::fclose(f_);
  if (!tmp_.empty()) ::unlink(tmp_.c_str());
}

void OutputFile::commit() {
  if (!f_) return;
  const bool failed = std::fflush(f_) != 0 || std::ferror(f_);
  const int err = errno;
  if (stdout_) {
    f_ = nullptr;
    if (failed) throw CliError(fmt::format("writing to standard output failed: {}", std::strerror(err)));
    return;
  }
  const bool closed = std::fclose(f_) == 0;
  f_ = nullptr;
  if (failed || !closed) {
    if (!tmp_.empty()) ::unlink(tmp_.c_str());
    throw CliError(fmt::format("writing {} failed: {}", path_, std::strerror(failed ? err : errno)));
  }
  if (!tmp_.empty() && std::rename(tmp_.c_str(), real_.c_str()) != 0) {
    const int e = errno;
    ::unlink(tmp_.c_str());
    throw CliError(fmt::format("cannot move the new file into {}: {}", path_, std::strerror(e)));
  }
}

}  // namespace nlsoft::host
