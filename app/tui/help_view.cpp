#include "app/tui/help_view.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "app/script/script_parser.hpp"
#include "app/tui/curses.hpp"
#include "app/tui/key_table.hpp"

namespace nlsoft::console::tui {

namespace {

// The panels' own keys: each panel reads them while it has the focus.
const char* const kPanelKeys[] = {
    "",
    "Parameters: Up/Down select, Enter edit in place (Esc cancels), u undo,",
    "            S save to a file, L load one (shows the diff before sending),",
    "            R reread, A send this session's edits again (after a firmware reset)",
    "Reference:  Left/Right kind, Enter edit a value, a send (CSV: upload)",
    "Runs:       Enter metrics, m mark, c compare with the marked run, e export CSV",
};

// A help line in pieces of at most `width` columns; continuations are
// indented to `indent` (the column where the line's description starts).
std::vector<std::string> wrap_help(const std::string& line, int width, size_t indent) {
  std::vector<std::string> out;
  std::string rest = line;
  while (int(rest.size()) > width && width > int(indent) + 10) {
    size_t cut = rest.rfind(' ', size_t(width));
    if (cut == std::string::npos || cut <= indent) cut = size_t(width);
    out.push_back(rest.substr(0, cut));
    const size_t next = rest.find_first_not_of(' ', cut);
    rest = std::string(indent, ' ') + (next == std::string::npos ? "" : rest.substr(next));
  }
  out.push_back(rest);
  return out;
}

}  // namespace

std::vector<std::string> help_lines() {
  std::vector<std::string> lines = {"nlsoft-console keys", ""};
  for (const std::string& l : key_help_lines()) lines.push_back(l);
  lines.insert(lines.end(), std::begin(kPanelKeys), std::end(kPanelKeys));
  return lines;
}

// Long lines wrap to the overlay's width, so it reads on 80 columns.
int draw_help(const Screen& screen, int rows, int cols, int top) {
  const int w = std::min(cols - 2, 100);
  std::vector<std::pair<std::string, bool>> lines;  // text, bold
  for (const std::string& l : help_lines())
    for (const auto& piece : wrap_help(l, w - 2, 12)) lines.emplace_back(piece, false);
  lines.emplace_back("Commands (':' line and --script files):", true);
  for (const auto& l : script_help())
    for (const auto& piece : wrap_help("  " + l, w - 2, 30)) lines.emplace_back(piece, false);
  const int total = int(lines.size());
  int h = std::min(rows - 2, total);
  // Taller than the terminal: the last row says where the view is and how
  // to move it, so nothing is silently cut.
  const bool scrolls = h < total;
  const int body = scrolls ? h - 1 : h;
  top = std::max(0, std::min(top, total - body));
  const int y0 = (rows - h) / 2, x0 = (cols - w) / 2;
  // Its rows blank across the whole width: the message and status rows it
  // covers show no letter either side of it.
  for (int r = 0; r < h; ++r) fill_row(y0 + r, 0, cols, 0);
  for (int r = 0; r < h; ++r) fill_row(y0 + r, x0, w, screen.attr(Role::Selected));
  for (int i = 0; i < body; ++i) {
    const auto& [text, bold] = lines[size_t(top + i)];
    put(y0 + i, x0 + 1, text, w - 2, screen.attr(Role::Selected) | (bold ? A_BOLD : 0));
  }
  if (scrolls)
    put(y0 + body, x0 + 1,
        fmt::format("-- lines {}-{} of {}: Up/Down, PgUp/PgDn scroll; any other key closes --", top + 1,
                    top + body, total),
        w - 2, screen.attr(Role::Selected) | A_BOLD);
  return top;
}

}  // namespace nlsoft::console::tui
