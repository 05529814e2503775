#include "host/files/input_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "host/files/cli_error.hpp"

namespace nlsoft::host {

namespace {

const char* type_name(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string bound_words(const InputKind& kind) {
  return kind.limit_words ? kind.limit_words : fmt::format("a {} is at most", kind.what);
}

void check_stat(const std::string& path, const struct stat& st, const InputKind& kind, bool stream_ok) {
  const bool fifo = S_ISFIFO(st.st_mode);
  if (!S_ISREG(st.st_mode) && !(fifo && stream_ok))
    throw CliError(fmt::format("cannot read {}: it is {}, not a {}", path, type_name(st.st_mode), kind.what));
  if (!fifo && uint64_t(st.st_size) > kind.max_bytes)
    throw CliError(fmt::format("cannot read {}: {}; {} {}", path, byte_size(uint64_t(st.st_size)), bound_words(kind),
                               byte_size(kind.max_bytes)));
}

struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string byte_size(uint64_t bytes) {
  if (bytes < 10 * 1024) return fmt::format("{} bytes", bytes);
  if (bytes < 1024 * 1024) return fmt::format("{:.1f} KiB", double(bytes) / 1024);
  if (bytes < 1024ull * 1024 * 1024) return fmt::format("{:.1f} MiB", double(bytes) / (1024 * 1024));
  return fmt::format("{:.1f} GiB", double(bytes) / (1024.0 * 1024 * 1024));
}

void check_input_file(const std::string& path, const InputKind& kind) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw CliError(fmt::format("{}: cannot read {}: {}", path, kind.what, std::strerror(errno)));
  check_stat(path, st, kind, false);
}

std::string read_input_file(const std::string& path, const InputKind& kind) {
  // O_NONBLOCK: opening a FIFO nobody writes to, or a device, must not hang
  // before the checks below refuse it.
  Fd f{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (f.fd < 0) throw CliError(fmt::format("{}: cannot read {}: {}", path, kind.what, std::strerror(errno)));
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) throw CliError(fmt::format("cannot read {}: {}", path, std::strerror(errno)));
  check_stat(path, st, kind, kind.stream_ok);
  std::string out;
  if (S_ISREG(st.st_mode)) out.reserve(size_t(st.st_size));
  // A FIFO stays on its one non-blocking descriptor (opening it again could
  // wait forever for a writer that already came and went), and waits in
  // poll: Linux reports POLLIN for data and POLLHUP only once a writer has
  // closed, so a FIFO whose writer has not opened it yet is not taken for an
  // empty one.
  const bool fifo = S_ISFIFO(st.st_mode);
  char buf[65536];
  while (true) {
    if (fifo) {
      pollfd p{f.fd, POLLIN, 0};
      if (::poll(&p, 1, -1) < 0) {
        if (errno == EINTR) continue;
        throw CliError(fmt::format("cannot read {}: {}", path, std::strerror(errno)));
      }
    }
    const ssize_t n = ::read(f.fd, buf, sizeof buf);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR || (fifo && errno == EAGAIN)) continue;
      throw CliError(fmt::format("cannot read {}: {}", path, std::strerror(errno)));
    }
    // A file that grows while read, or a FIFO: bounded all the same.
    if (out.size() + size_t(n) > kind.max_bytes)
      throw CliError(fmt::format("cannot read {}: more than {}; {} {}", path, byte_size(kind.max_bytes),
                                 bound_words(kind), byte_size(kind.max_bytes)));
    out.append(buf, size_t(n));
  }
  return out;
}

}  // namespace nlsoft::host
