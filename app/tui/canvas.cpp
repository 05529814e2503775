#include "app/tui/canvas.hpp"

#include <cstdlib>

#include "app/tui/curses.hpp"

namespace nlsoft::console::tui {

namespace {
// Braille dot bits by (column, row) inside a cell (Unicode U+2800 block).
constexpr uint8_t kDot[2][4] = {{0x01, 0x02, 0x04, 0x40}, {0x08, 0x10, 0x20, 0x80}};
}  // namespace

Canvas::Canvas(int cols, int rows, bool braille)
    : cols_(cols > 0 ? cols : 0),
      rows_(rows > 0 ? rows : 0),
      dx_(braille ? 2 : 1),
      dy_(braille ? 4 : 1),
      braille_(braille),
      bits_(size_t(cols_ * rows_), 0),
      series_(size_t(cols_ * rows_), 0) {}

void Canvas::dot(int x, int y, uint8_t series) {
  if (x < 0 || y < 0 || x >= width() || y >= height()) return;
  const size_t cell = size_t((y / dy_) * cols_ + x / dx_);
  // Spelled out: under UBSan, GCC loses the range of kDot's element and
  // warns (-Wconversion) on `|=` with the int it promotes to.
  const uint8_t dot = braille_ ? kDot[x % 2][y % 4] : uint8_t(1);
  bits_[cell] = uint8_t(bits_[cell] | dot);
  series_[cell] = series;
}

void Canvas::line(int x0, int y0, int x1, int y1, uint8_t series) {
  // Bresenham; long jumps (a step or a wrap) are clipped by dot().
  const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  for (int guard = 0; guard < 100000; ++guard) {
    dot(x0, y0, series);
    if (x0 == x1 && y0 == y1) break;
    const int e2 = 2 * err;
    if (e2 >= dy) err += dy, x0 += sx;
    if (e2 <= dx) err += dx, y0 += sy;
  }
}

void Canvas::draw(int y, int x, const int* attrs, const char* glyphs) const {
  for (int r = 0; r < rows_; ++r) {
    for (int c = 0; c < cols_; ++c) {
      const size_t cell = size_t(r * cols_ + c);
      if (!bits_[cell]) continue;
      attrset(attrs[series_[cell]]);
      if (braille_) {
        const wchar_t w[2] = {wchar_t(0x2800 + bits_[cell]), 0};
        mvaddnwstr(y + r, x + c, w, 1);
      } else {
        mvaddch(y + r, x + c, chtype(static_cast<unsigned char>(glyphs[series_[cell]])));
      }
    }
  }
  attrset(A_NORMAL);
}

}  // namespace nlsoft::console::tui
