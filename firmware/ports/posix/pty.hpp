#pragma once
// A pseudo-terminal whose slave side plays the board's serial port.
#include <string>

namespace nlsoft::fw::posix {

struct Pty {
  int master = -1;
  int slave_keepalive = -1;  // our own slave fd: keeps the master usable while no console is attached
  std::string path;
};

// Opens a raw, non-blocking pty; returns false with errno set on failure.
bool open_pty(Pty& out);

}  // namespace nlsoft::fw::posix
