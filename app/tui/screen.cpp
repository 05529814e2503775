#include "app/tui/screen.hpp"

#include <langinfo.h>

#include <clocale>
#include <cstdlib>
#include <cstring>

#include "app/tui/curses.hpp"

namespace nlsoft::console::tui {

Screen::Screen() {
  std::setlocale(LC_ALL, "");
  const char* cs = nl_langinfo(CODESET);
  const char* ascii = std::getenv("NLSOFT_ASCII");
  utf8_ = cs && std::strcmp(cs, "UTF-8") == 0 && !(ascii && *ascii && *ascii != '0');
  initscr();
  cbreak();
  noecho();
  keypad(stdscr, TRUE);
  curs_set(0);
  set_escdelay(25);
  timeout(40);  // getch() returns at least 25 times a second: the redraw clock
  const char* no_colour = std::getenv("NO_COLOR");
  colour_ = has_colors() && !(no_colour && *no_colour);
  if (colour_) {
    start_color();
    use_default_colors();
    init_pair(1, COLOR_BLACK, COLOR_CYAN);   // title, key labels
    init_pair(2, COLOR_YELLOW, -1);          // y_ref
    init_pair(3, COLOR_CYAN, -1);            // y_hat
    init_pair(4, COLOR_GREEN, -1);           // y_true, ok
    init_pair(5, COLOR_YELLOW, -1);          // pending
    init_pair(6, COLOR_RED, -1);             // error
    init_pair(7, COLOR_WHITE, COLOR_BLUE);   // selection
    init_pair(8, COLOR_BLUE, -1);            // borders
    init_pair(9, COLOR_MAGENTA, -1);         // warnings
  }
}

Screen::~Screen() {
  curs_set(1);
  endwin();
}

int Screen::attr(Role r) const {
  if (!colour_) {
    switch (r) {
      case Role::Title:
      case Role::KeyLabel:
      case Role::Selected: return A_REVERSE;
      case Role::KeyName:
      case Role::Error:
      case Role::Warn: return A_BOLD;
      case Role::Dim:
      case Role::Border: return A_DIM;
      case Role::Pending: return A_UNDERLINE;
      default: return A_NORMAL;
    }
  }
  switch (r) {
    case Role::Title: return int(COLOR_PAIR(1)) | A_BOLD;
    case Role::KeyLabel: return int(COLOR_PAIR(1));
    case Role::KeyName: return A_BOLD;
    case Role::Ref: return int(COLOR_PAIR(2));
    case Role::Hat: return int(COLOR_PAIR(3));
    case Role::True:
    case Role::Ok: return int(COLOR_PAIR(4));
    case Role::Pending: return int(COLOR_PAIR(5));
    case Role::Error: return int(COLOR_PAIR(6)) | A_BOLD;
    case Role::Selected: return int(COLOR_PAIR(7));
    case Role::Border: return int(COLOR_PAIR(8));
    case Role::Warn: return int(COLOR_PAIR(9)) | A_BOLD;
    case Role::Dim: return A_DIM;
    case Role::Normal: return A_NORMAL;
  }
  return A_NORMAL;
}

int Screen::series_attr(int i) const {
  if (!colour_) return A_NORMAL;
  static const short kPairs[] = {3, 4, 2, 9, 6, 8};
  return int(COLOR_PAIR(kPairs[size_t(i) % (sizeof(kPairs) / sizeof(kPairs[0]))]));
}

int Screen::rows() const { return LINES; }
int Screen::cols() const { return COLS; }

void put(int y, int x, const std::string& s, int width, int a) {
  if (width <= 0 || y < 0 || y >= LINES || x >= COLS) return;
  if (x + width > COLS) width = COLS - x;
  attrset(a);
  // Count UTF-8 code points, not bytes, against the width.
  int cols = 0;
  size_t end = 0;
  while (end < s.size() && cols < width) {
    const unsigned char c = static_cast<unsigned char>(s[end]);
    const size_t len = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : 4;
    end += len;
    ++cols;
  }
  mvaddnstr(y, x, s.c_str(), int(std::min(end, s.size())));
  attrset(A_NORMAL);
}

void fill_row(int y, int x, int width, int a) {
  if (width <= 0 || y < 0 || y >= LINES) return;
  attrset(a);
  mvhline(y, x, ' ', width);
  attrset(A_NORMAL);
}

}  // namespace nlsoft::console::tui
