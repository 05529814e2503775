#pragma once
// Baud rates outside the POSIX B* constants (250000, 1000000, ...): Linux
// takes any integer through termios2/BOTHER. Kept in its own translation
// unit because <asm/termbits.h> clashes with <termios.h>.
#include <string>

namespace nlsoft::console {

// Returns an empty string on success, otherwise why it failed.
std::string set_custom_baud(int fd, unsigned baud);

}  // namespace nlsoft::console
