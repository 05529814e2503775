#pragma once
// What the console prints on the normal terminal when the TUI ends: the
// runs this session recorded (id, duration, samples, label), where they
// are, and the command that shows one, so nobody has to remember the
// database path the title bar showed.
#include <string>

#include "app/live/live_console.hpp"

namespace nlsoft::console::tui {

std::string exit_summary(LiveConsole& console);

}  // namespace nlsoft::console::tui
