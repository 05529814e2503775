#pragma once
// A dot canvas over terminal cells: 2x4 braille dots per cell on UTF-8
// terminals, one character per cell otherwise. Each cell remembers the last
// series drawn into it, which picks its colour (or its ASCII glyph).
#include <cstdint>
#include <vector>

namespace nlsoft::console::tui {

class Canvas {
 public:
  Canvas(int cols, int rows, bool braille);
  int width() const { return cols_ * dx_; }   // in dots
  int height() const { return rows_ * dy_; }
  void dot(int x, int y, uint8_t series);
  void line(int x0, int y0, int x1, int y1, uint8_t series);
  // Renders at screen (y, x); attrs[s] is the attribute of series s,
  // glyphs[s] its ASCII character.
  void draw(int y, int x, const int* attrs, const char* glyphs) const;

 private:
  int cols_, rows_, dx_, dy_;
  bool braille_;
  std::vector<uint8_t> bits_, series_;
};

}  // namespace nlsoft::console::tui
