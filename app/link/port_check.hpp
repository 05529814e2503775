#pragma once
// What a port must be before the console talks on it: a terminal, and held
// by this console alone. Each check returns "" when it passes, else the
// reason in words.
#include <string>

namespace nlsoft::console {

// A regular file, /dev/null or a socket opened as "the port" would swallow
// requests and time out with a misleading message; say what it is instead.
// fd < 0: the path could not be opened as a terminal; stat() tells what it is.
std::string check_terminal(int fd, const std::string& path);

// Two consoles on one port each steal bytes from the other's replies, so
// the port is taken exclusively: TIOCEXCL (refuses other opens, root
// excepted) and an advisory flock (which root's consoles honour too). On
// a port held by another process, names its PID and command where
// /proc/locks tells.
std::string take_exclusive(int fd, const std::string& path);

// A program that opened the port before this console (`cat /dev/pts/5 &`)
// takes bytes meant for the console, which then sees some frames and misses
// replies: refused, naming the program's PID and command
// (app/link/port_openers.hpp).
std::string check_no_other_reader(int fd, const std::string& path);

// Pseudo-terminals refuse some line settings (parity, stop bits, flow
// control) and carry bytes all the same; a real port that refuses one is an
// error.
bool is_pseudo_terminal(int fd);

}  // namespace nlsoft::console
