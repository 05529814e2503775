#include "firmware/ports/posix/file_flash.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace nlsoft::fw::posix {

namespace {

constexpr uint32_t kFileSize = FileFlash::kSectorSize * FileFlash::kSectors;

bool write_all(int fd, const uint8_t* p, size_t len, off_t at) {
  while (len > 0) {
    const ssize_t w = ::pwrite(fd, p, len, at);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w, len -= size_t(w), at += w;
  }
  return true;
}

}  // namespace

FileFlash::~FileFlash() {
  if (fd_ >= 0) ::close(fd_);
}

FileFlash::Opened FileFlash::open(const std::string& path, std::string& error) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  if (fd < 0) {
    error = "cannot open settings file '" + path + "': " + std::strerror(errno);
    return Opened::Failed;
  }
  // One simulator per file: two writing the same sectors would be two
  // boards on one flash chip.
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    error = "settings file '" + path + "' is in use by another simulator";
    ::close(fd);
    return Opened::Busy;
  }
  struct stat st {};
  ::fstat(fd, &st);
  if (st.st_size == 0) {
    const std::vector<uint8_t> erased(kFileSize, 0xFF);
    if (!write_all(fd, erased.data(), erased.size(), 0) || ::fsync(fd) != 0) {
      error = "cannot write settings file '" + path + "': " + std::strerror(errno);
      ::close(fd);
      return Opened::Failed;
    }
  } else if (st.st_size != off_t(kFileSize)) {
    error = "settings file '" + path + "' is " + std::to_string(st.st_size) + " bytes, not the " +
            std::to_string(kFileSize) + " of two 16 KiB sectors: not a simulator's settings file";
    ::close(fd);
    return Opened::Failed;
  }
  fd_ = fd;
  return Opened::Ok;
}

bool FileFlash::erase(int sector) {
  if (fd_ < 0 || sector < 0 || sector >= kSectors) return false;
  const std::vector<uint8_t> erased(kSectorSize, 0xFF);
  return write_all(fd_, erased.data(), erased.size(), off_t(sector_base(sector))) && ::fdatasync(fd_) == 0;
}

bool FileFlash::program(uint32_t addr, const uint8_t* data, size_t len) {
  if (fd_ < 0 || uint64_t(addr) + len > kFileSize) return false;
  std::vector<uint8_t> cell(len);
  read(addr, cell.data(), len);
  for (size_t i = 0; i < len; ++i) cell[i] &= data[i];  // programming clears bits, never sets one
  return write_all(fd_, cell.data(), len, off_t(addr)) && ::fdatasync(fd_) == 0;
}

void FileFlash::read(uint32_t addr, uint8_t* out, size_t len) const {
  std::memset(out, 0xFF, len);
  if (fd_ < 0 || uint64_t(addr) + len > kFileSize) return;
  size_t got = 0;
  while (got < len) {
    const ssize_t r = ::pread(fd_, out + got, len - got, off_t(addr + got));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return;
    got += size_t(r);
  }
}

}  // namespace nlsoft::fw::posix
