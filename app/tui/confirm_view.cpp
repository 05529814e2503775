#include "app/tui/confirm_view.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "app/tui/curses.hpp"

namespace nlsoft::console::tui {

void draw_confirm(const Screen& screen, int rows, int cols, const std::string& title,
                  const std::vector<std::string>& lines) {
  const int w = std::min(cols - 4, 90);
  const int h = std::min(rows - 4, int(lines.size()) + 4);
  const int y0 = (rows - h) / 2, x0 = (cols - w) / 2;
  // A blank margin round the box: no plot dot touches it, so it reads as a
  // box over the screen, not as more lines of the plot.
  // Where the margin would leave a column or two of the screen beside it
  // (80 columns: a lone letter at the left edge, a border's end at the
  // right), it reaches the edge instead.
  const int left = x0 - 1 <= 2 ? 0 : x0 - 1, right = x0 + w + 1 >= cols - 2 ? cols : x0 + w + 1;
  for (int r = -1; r <= h; ++r) fill_row(y0 + r, left, right - left, 0);
  for (int r = 0; r < h; ++r) fill_row(y0 + r, x0, w, screen.attr(Role::Selected));
  put(y0, x0 + 1, title, w - 2, screen.attr(Role::Selected) | A_BOLD);
  for (int i = 0; i < h - 4 && size_t(i) < lines.size(); ++i)
    put(y0 + 2 + i, x0 + 2, lines[size_t(i)], w - 4, screen.attr(Role::Selected));
  if (int(lines.size()) > h - 4)
    put(y0 + h - 2, x0 + 2, fmt::format("... and {} more", int(lines.size()) - (h - 4)), w - 4,
        screen.attr(Role::Selected));
  put(y0 + h - 1, x0 + 1, "y: yes   n/Esc: no", w - 2, screen.attr(Role::Selected) | A_BOLD);
}

}  // namespace nlsoft::console::tui
