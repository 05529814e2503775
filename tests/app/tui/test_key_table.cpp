// The key table makes the help's key lines, the key bar and the dispatch:
// each key it binds is named in the help, found again by its code, and the
// bar shows only keys it binds.
#include <gtest/gtest.h>

#include <cctype>
#include <set>
#include <string>

#include "app/tui/help_view.hpp"
#include "app/tui/key_table.hpp"
#include "app/tui/status_bar.hpp"

namespace nlsoft::console::tui {
namespace {

std::string help_text() {
  std::string s;
  for (const std::string& l : help_lines()) s += l + "\n";
  return s;
}

// `name` in `text` not as part of a longer word ("F1" is not in "F10").
bool names(const std::string& text, const std::string& name) {
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; };
  for (size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
    const bool open = at == 0 || !word(text[at - 1]) || !word(name.front());
    const size_t end = at + name.size();
    const bool close = end == text.size() || !word(text[end]) || !word(name.back());
    if (open && close) return true;
  }
  return false;
}

TEST(TuiKeyTable, EveryNamedKeyIsInTheHelp) {
  const std::string help = help_text();
  for (const KeyBinding& b : key_table())
    for (const KeyName& k : b.keys)
      if (*k.name) {
        EXPECT_TRUE(names(help, k.name)) << k.name << " is bound but not in the help:\n" << help;
      }
}

TEST(TuiKeyTable, EveryKeyDispatchesToItsBinding) {
  for (const KeyBinding& b : key_table()) {
    if (b.action == KeyAction::None) continue;  // a command's help row: no key
    ASSERT_FALSE(b.keys.empty()) << key_names(b);
    for (const KeyName& k : b.keys) EXPECT_EQ(key_binding(k.code), &b) << key_names(b) << ": code " << k.code;
  }
}

TEST(TuiKeyTable, EveryActionHasExactlyOneBinding) {
  for (int a = int(KeyAction::None) + 1; a <= int(KeyAction::Restart); ++a) {
    int bound = 0;
    for (const KeyBinding& b : key_table()) bound += int(b.action) == a;
    EXPECT_EQ(bound, 1) << "action " << a;
  }
}

TEST(TuiKeyTable, APanelsKeyIsNotTheConsoles) {
  // The panels read these while they have the focus (undo, edit, mark).
  for (int code : {'u', '\n', 'm', 'S', 'L', 'A'}) EXPECT_EQ(key_binding(code), nullptr) << char(code);
}

TEST(TuiKeyTable, TheKeyBarShowsTheTablesBarKeysInBarOrder) {
  for (bool restart : {false, true}) {
    const auto bar = bar_bindings(restart);
    const auto items = key_bar_items(400, restart);
    ASSERT_EQ(items.size(), bar.size());
    std::set<std::string> seen;
    for (size_t i = 0; i < bar.size(); ++i) {
      EXPECT_EQ(items[i].first, bar[i]->keys.front().name);
      EXPECT_EQ(key_binding(bar[i]->keys.front().code), bar[i]);
      EXPECT_TRUE(seen.insert(items[i].first).second) << items[i].first << " twice on the bar";
      if (i > 0 && !bar[i - 1]->while_down) {
        EXPECT_LT(bar[i - 1]->bar, bar[i]->bar);
      }
    }
    EXPECT_EQ(seen.count("R"), restart ? 1u : 0u);
  }
}

}  // namespace
}  // namespace nlsoft::console::tui
