#include "firmware/ports/posix/pty.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cstdlib>

namespace nlsoft::fw::posix {

bool open_pty(Pty& out) {
  const int m = posix_openpt(O_RDWR | O_NOCTTY);
  if (m < 0) return false;
  if (grantpt(m) != 0 || unlockpt(m) != 0) return close(m), false;
  const char* name = ptsname(m);
  if (!name) return close(m), false;
  // Holding the slave open ourselves keeps reads from failing with EIO
  // between consoles, so the firmware runs on whether or not one is attached.
  const int s = open(name, O_RDWR | O_NOCTTY);
  if (s < 0) return close(m), false;
  termios t{};
  tcgetattr(s, &t);
  cfmakeraw(&t);  // binary-safe: no echo, no CR/LF translation, no signals
  tcsetattr(s, TCSANOW, &t);
  fcntl(m, F_SETFL, fcntl(m, F_GETFL) | O_NONBLOCK);
  out.master = m;
  out.slave_keepalive = s;
  out.path = name;
  return true;
}

}  // namespace nlsoft::fw::posix
