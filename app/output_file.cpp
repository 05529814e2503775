#include "app/output_file.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "app/cli_error.hpp"

namespace nlsoft::console {

OutputFile::OutputFile(const std::string& path) : path_(path) {
  if (path == "-") {
    f_ = stdout;
    stdout_ = true;
    return;
  }
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode)) throw CliError(fmt::format("cannot write {}: it is a directory", path));
    f_ = std::fopen(path.c_str(), "w");
    if (!f_) throw CliError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
    return;
  }
  // mkstemp beside the target: same file system, so the rename is atomic
  std::string tmpl = path + ".XXXXXX";
  const int fd = ::mkstemp(tmpl.data());
  if (fd < 0) throw CliError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  ::fchmod(fd, 0644);
  f_ = ::fdopen(fd, "w");
  if (!f_) {
    ::close(fd);
    ::unlink(tmpl.c_str());
    throw CliError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
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
  if (!tmp_.empty() && std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const int e = errno;
    ::unlink(tmp_.c_str());
    throw CliError(fmt::format("cannot move the new file into {}: {}", path_, std::strerror(e)));
  }
}

}  // namespace nlsoft::console
