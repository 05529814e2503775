#include "app/tui/key_table.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "app/tui/curses.hpp"

namespace nlsoft::console::tui {

namespace {

using A = KeyAction;
using H = HelpPlace;

// In help order; the bar's order is each binding's `bar`.
const std::vector<KeyBinding> kTable = {
    {A::Help, {{KEY_F(1), "F1"}, {'?', "?"}}, H::Row,
     {"this help: Up/Down/PgUp/PgDn scroll it, any other key closes it", "(Esc, ?, F1, q, Enter or Space only close)"},
     1, "Help", "Help", 10},
    {A::FocusParams, {{KEY_F(2), "F2"}}, H::Row, {"focus parameters / reference / runs (Tab cycles)"}, 2, "Params", "Par", 2},
    {A::FocusRef, {{KEY_F(3), "F3"}}, H::Joined, {}, 3, "Ref", "Ref", 1},
    {A::FocusRuns, {{KEY_F(4), "F4"}}, H::Joined, {}, 4, "Runs", "Runs", 0},
    // Shift-Tab cycles the other way.
    {A::CycleFocus, {{'\t', "Tab"}, {KEY_BTAB, ""}}, H::InText, {}},
    {A::Messages, {{KEY_F(9), "F9"}}, H::Row,
     {"messages with their times (Up/Down/PgUp scroll back); also in <db>.session.log"}},
    {A::Start, {{KEY_F(5), "F5"}}, H::Row, {"start a run (recorded)"}, 5, "Start", "Start", 9},
    {A::Stop, {{KEY_F(6), "F6"}}, H::Beside, {"stop the run"}, 6, "Stop", "Stop", 8},
    {A::Hold, {{KEY_F(7), "F7"}}, H::Row, {"hold / resume"}, 7, "Hold", "Hold", 4},
    {A::Neutral, {{KEY_F(8), "F8"}}, H::Beside, {"actuators neutral"}, 8, "Neutral", "Neut", 3},
    {A::PathView, {{'v', "v"}}, H::Row, {"time plots <-> 2-D path"}, 10, "View", "View", 6},
    {A::PathAxes, {{'x', "x"}}, H::Beside, {"change the path's axes"}},
    {A::Panel, {{'w', "w"}}, H::Row, {"hide / show the side panel (the plot takes the whole width);", "F2 F3 F4 F9 show it again"},
     11, "Panel", "Panel", 7},
    {A::PlotSignal, {{'p', "p"}}, H::Row, {"plot signal: y, u, cost, iter, compute, ident (u, y, sensors)  (or :plot u)"}},
    {A::None, {{0, ":overlay ID"}}, H::Row, {"a recorded run under the live plot ('o'); :overlay off"}},
    {A::ZoomIn, {{'+', "+"}}, H::Row, {"zoom in (shorter window) / out"}},
    {A::ZoomOut, {{'-', "-"}}, H::Joined, {}},
    {A::Tuning, {{'t', "t"}}, H::Row, {"the tuning view under the plot on/off (:tune shows it)"}},
    {A::Pause, {{' ', "Space"}}, H::Row, {"pause the plot (recording goes on)"}},
    {A::ScrollBack, {{'[', "["}}, H::Beside, {"scroll back / forward"}},
    {A::ScrollForward, {{']', "]"}}, H::Joined, {}},
    {A::CursorBack, {{'<', "<"}, {',', ""}}, H::Row, {"time cursor on a paused plot: the readout gives the values at it"}},
    {A::CursorForward, {{'>', ">"}, {'.', ""}}, H::Joined, {}},
    {A::CommandLine, {{':', ":"}}, H::Row,
     {"command line: the script commands (set, get, ref, run, expect, ...);",
      "Tab completes commands, parameter names and options"},
     9, "Cmd", "Cmd", 5},
    {A::SaveSettings, {{'W', "W"}}, H::Row,
     {"keep the parameters in force in the firmware's flash (they survive",
      "a reset; :settings defaults brings the built-in ones back)"}},
    {A::Quit, {{'q', "q"}, {KEY_F(10), "F10"}}, H::Row, {"quit (asks first while a run is active)"}, 12, "Quit", "Quit", 11},
    {A::Restart, {{'R', "R"}}, H::Row,
     {"with --sim, once the simulator has ended (killed, crashed): start it again and",
      "reconnect (the key bar shows R Restart meanwhile)"},
     0, "Restart", "Restart", 12, true},
};

// The help's columns: names from column 2, descriptions from 12, a second
// binding on the line from 39; each at least two spaces after what precedes.
constexpr size_t kDescColumn = 12, kBesideColumn = 39;

std::string pad(const std::string& s, size_t width, size_t gap) { return fmt::format("{:<{}}", s, std::max(width, s.size() + gap)); }

}  // namespace

const std::vector<KeyBinding>& key_table() { return kTable; }

const KeyBinding* key_binding(int code) {
  for (const KeyBinding& b : kTable)
    if (b.action != KeyAction::None)
      for (const KeyName& k : b.keys)
        if (k.code == code) return &b;
  return nullptr;
}

std::string key_names(const KeyBinding& b) {
  std::string s;
  for (const KeyName& k : b.keys)
    if (*k.name) s += (s.empty() ? "" : " ") + std::string(k.name);
  return s;
}

std::vector<std::string> key_help_lines() {
  struct Line {
    std::string names, beside_names;
    std::vector<std::string> help;
    std::string beside;
  };
  std::vector<Line> lines;
  for (const KeyBinding& b : kTable) {
    switch (b.place) {
      case HelpPlace::Row: lines.push_back({key_names(b), "", b.help, ""}); break;
      case HelpPlace::Beside:
        lines.back().beside_names = key_names(b);
        lines.back().beside = b.help.front();
        break;
      case HelpPlace::Joined: {
        Line& l = lines.back();
        (l.beside_names.empty() ? l.names : l.beside_names) += " " + key_names(b);
        break;
      }
      case HelpPlace::InText: break;
    }
  }
  std::vector<std::string> out;
  for (const Line& l : lines) {
    std::string first = "  " + pad(l.names, kDescColumn - 2, 2) + l.help.front();
    if (!l.beside_names.empty()) first = pad(first, kBesideColumn, 3) + pad(l.beside_names, 4, 2) + l.beside;
    out.push_back(first);
    for (size_t i = 1; i < l.help.size(); ++i) out.push_back(std::string(kDescColumn, ' ') + l.help[i]);
  }
  return out;
}

std::vector<const KeyBinding*> bar_bindings(bool restart) {
  std::vector<const KeyBinding*> bar;
  for (const KeyBinding& b : kTable)
    if (b.bar > 0) bar.push_back(&b);
  std::sort(bar.begin(), bar.end(), [](const KeyBinding* a, const KeyBinding* b) { return a->bar < b->bar; });
  if (restart)
    for (const KeyBinding& b : kTable)
      if (b.while_down) bar.insert(bar.begin(), &b);
  return bar;
}

}  // namespace nlsoft::console::tui
