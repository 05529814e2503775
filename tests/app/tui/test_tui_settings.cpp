// W in the TUI (SETTINGS save, PROTOCOL.md 9.11), as a person uses it in
// tmux: a parameter edited and kept with W is in force in the next console
// with the same database, whose simulator starts from the settings file
// beside it; a simulator that keeps no settings gets W refused in words.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "app/support/temp_dir.hpp"
#include "app/support/tmux_console.hpp"

namespace nlsoft::console {
namespace {

using namespace tui_test;

void quit(Tmux& t) {
  t.keys("q");
  for (int i = 0; i < 50; ++i) {
    if (contains(t.screen(), "EXIT=")) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

TEST(ConsoleTuiSettings, WKeepsTheParametersForTheNextSimulator) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string args = "--sim hasel --db " + shell_quote(dir.file("runs.db"));
  {
    Tmux t = console_in(args, 120, 40);
    ASSERT_TRUE(t.started()) << t.error();
    std::string s;
    ASSERT_TRUE(t.wait_for(panel_read, s)) << s;
    t.keys(": 'set Lambda 0.5' Enter");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "Lambda = 0.5 0.5 0.5 0.5 0.5 0.5"); }, s))
        << s;
    t.keys("W");
    // The console's line, then the firmware's LOG right after it on the message line.
    ASSERT_TRUE(t.wait_for([](const std::string& x) {
      return contains(x, "settings saved") || contains(x, "settings: saved to flash");
    }, s)) << s;
    t.keys("?");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "keep the parameters in force in the firmware"); },
                           s))
        << s;
    t.keys("Escape");
    quit(t);
  }
  Tmux t = console_in(args, 120, 40);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_for(panel_read, s)) << s;
  t.keys("F9");
  // The message list wraps its lines: "settings: from flash," then "save 1 (17 values)".
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "settings: from flash,") && contains(x, "save 1 ("); },
                         s))
      << s;
  t.keys(": 'get Lambda' Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "Lambda = 0.5 0.5 0.5 0.5 0.5 0.5"); }, s)) << s;
  quit(t);
}

TEST(ConsoleTuiSettings, WWithoutASettingsStoreSaysSo) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  Tmux t = console_in("--sim hasel --no-record", 120, 40);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_for(panel_read, s)) << s;
  t.keys("W");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "keeps no settings"); }, s)) << s;
  quit(t);
}

}  // namespace
}  // namespace nlsoft::console
