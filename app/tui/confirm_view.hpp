#pragma once
// The yes/no box over the screen (a diff before it is sent, quitting
// during a run).
#include <string>
#include <vector>

#include "app/tui/screen.hpp"

namespace nlsoft::console::tui {

void draw_confirm(const Screen& screen, int rows, int cols, const std::string& title,
                  const std::vector<std::string>& lines);

}  // namespace nlsoft::console::tui
