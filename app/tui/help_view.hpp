#pragma once
// The help (F1, ?): the key table's lines, the panels' keys and the script
// commands, over the whole screen.
#include <string>
#include <vector>

#include "app/tui/screen.hpp"

namespace nlsoft::console::tui {

// The help's lines before the commands: a title, the key table's lines, the
// panels' keys.
std::vector<std::string> help_lines();

// Draws the help on a rows x cols screen from line `top` on (a terminal
// shorter than the help scrolls it); returns `top` kept within the help.
int draw_help(const Screen& screen, int rows, int cols, int top);

}  // namespace nlsoft::console::tui
