#pragma once
// Terminal setup and the look: colours when the terminal has them (and
// NO_COLOR is unset), attributes otherwise; braille plots on a UTF-8 locale,
// ASCII elsewhere (or with NLSOFT_ASCII=1).
#include <string>

namespace nlsoft::console::tui {

enum class Role {
  Normal, Title, KeyLabel, KeyName, Ref, Hat, True, Ok, Pending, Error, Dim, Selected, Border, Warn,
};

class Screen {
 public:
  Screen();   // initscr and friends
  ~Screen();  // endwin: the terminal is always restored
  Screen(const Screen&) = delete;
  Screen& operator=(const Screen&) = delete;

  bool utf8() const { return utf8_; }
  bool colour() const { return colour_; }
  // What ends a shortened text: one column either way.
  const char* ellipsis() const { return utf8_ ? "\u2026" : "~"; }
  // Attribute for a role: a colour pair, or bold/reverse/dim in monochrome.
  int attr(Role r) const;
  // Attribute of the i-th trace of a plot with several of one kind (u0, u1,
  // ...): colours in turn; plain in monochrome, where glyphs tell them apart.
  int series_attr(int i) const;
  int rows() const;
  int cols() const;

 private:
  bool utf8_ = false, colour_ = false;
};

// Writes at most `width` columns of s at (y, x) with attribute a.
void put(int y, int x, const std::string& s, int width, int a = 0);
// Fills the rest of row y from x with blanks in attribute a.
void fill_row(int y, int x, int width, int a);

}  // namespace nlsoft::console::tui
