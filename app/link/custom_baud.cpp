#include "app/link/custom_baud.hpp"

#include <cerrno>
#include <cstring>

#if defined(__linux__)
#include <asm/termbits.h>
#include <sys/ioctl.h>
#endif

namespace nlsoft::console {

std::string set_custom_baud(int fd, unsigned baud) {
#if defined(__linux__)
  struct termios2 tio {};
  if (ioctl(fd, TCGETS2, &tio) != 0) return std::strerror(errno);
  tio.c_cflag &= ~static_cast<tcflag_t>(CBAUD);
  tio.c_cflag |= BOTHER;
  tio.c_ispeed = baud;
  tio.c_ospeed = baud;
  if (ioctl(fd, TCSETS2, &tio) != 0) return std::strerror(errno);
  return {};
#else
  (void)fd;
  (void)baud;
  return "this system only supports the standard baud rates";
#endif
}

}  // namespace nlsoft::console
