#pragma once
// The selection cursor every list panel shares: Up/k, Down/j, PgUp, PgDn.
#include <algorithm>
#include <cstddef>

#include "app/tui/curses.hpp"

namespace nlsoft::console::tui {

// Moves `selected` within [0, n) for a navigation key; false for any other key.
inline bool move_cursor(int ch, size_t& selected, size_t n) {
  switch (ch) {
    case KEY_UP:
    case 'k':
      if (selected > 0) --selected;
      return true;
    case KEY_DOWN:
    case 'j':
      if (selected + 1 < n) ++selected;
      return true;
    case KEY_PPAGE: selected = selected > 10 ? selected - 10 : 0; return true;
    case KEY_NPAGE: selected = n ? std::min(n - 1, selected + 10) : 0; return true;
    default: return false;
  }
}

}  // namespace nlsoft::console::tui
