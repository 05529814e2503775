#pragma once
// The console's own keys, each written once: the help's key lines, the key
// bar and the dispatch are all made from this table, so a key cannot be
// bound without being shown, nor shown without being bound.
#include <string>
#include <vector>

namespace nlsoft::console::tui {

enum class KeyAction {
  None,  // a help row for a command that has no key of its own (:overlay)
  Help,
  FocusParams,
  FocusRef,
  FocusRuns,
  CycleFocus,
  Messages,
  Start,
  Stop,
  Hold,
  Neutral,
  PathView,
  PathAxes,
  Panel,
  PlotSignal,
  ZoomIn,
  ZoomOut,
  Tuning,
  Pause,
  ScrollBack,
  ScrollForward,
  CursorBack,
  CursorForward,
  CommandLine,
  Quit,
  Restart,
  SaveSettings,
};

// A key code (ncurses') and the name the help and the bar give it; an alias
// the help does not list has no name.
struct KeyName {
  int code;
  const char* name;
};

// Where a binding shows in the help's key lines.
enum class HelpPlace {
  Row,     // starts a line: its names, then its description
  Joined,  // its names join the previous binding's: one description for both
  Beside,  // the second column of the previous binding's line
  InText,  // named inside the previous binding's description
};

struct KeyBinding {
  KeyAction action;
  std::vector<KeyName> keys;
  HelpPlace place;
  std::vector<std::string> help;  // the description; further lines continue it
  // On the key bar: its place (0: not on it), its label on a wide bar, the
  // brief one on a narrow bar, and `keep`: the lowest labels go first when
  // even the brief ones do not fit.
  int bar = 0;
  const char* label = "";
  const char* brief = "";
  int keep = 0;
  bool while_down = false;  // on the bar only while the simulator has ended, leading it
};

const std::vector<KeyBinding>& key_table();
// The binding a key code belongs to; null when the console has none (a
// panel's key).
const KeyBinding* key_binding(int code);
// The help's key lines, in table order.
std::vector<std::string> key_help_lines();
// The bindings on the key bar, in bar order; with `restart` (the simulator
// has ended) the one shown only then leads.
std::vector<const KeyBinding*> bar_bindings(bool restart);
// A binding's names as the help writes them: "F1 ?".
std::string key_names(const KeyBinding& b);

}  // namespace nlsoft::console::tui
