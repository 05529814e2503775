// What the TUI says, as a newcomer reads it at the two sizes terminals open
// at (80x24, 120x40): an edit that replaces the value it opens with and says
// so, a quit that does not promise to keep what --no-record drops, text
// shortened by words (never inside a number), a help with nothing beside
// it. Driven in tmux as a person would (tmux_console.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/progress_bar.hpp"
#include "app/support/temp_dir.hpp"
#include "app/support/tmux_console.hpp"

namespace nlsoft::console {
namespace {

using namespace tui_test;

struct Size {
  int cols, rows;
};
const Size kSizes[] = {{80, 24}, {120, 40}};

std::string size_name(const Size& z) { return std::to_string(z.cols) + "x" + std::to_string(z.rows); }

// The row of the parameter panel that shows `name`'s value (the panel
// pads names to 8 columns on 80 columns, 12 wider).
std::string value_row(const std::string& screen, const std::string& name, const Size& z) {
  std::string padded = name;
  padded.resize(z.cols < 100 ? 8 : 12, ' ');
  return line_with(screen, " " + padded);
}

// Columns of a captured row (its trailing blanks are not captured).
int columns(const std::string& row) {
  int n = 0;
  for (unsigned char c : row) n += (c & 0xC0) != 0x80;
  return n;
}

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(' '), b = s.find_last_not_of(' ');
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// `shown` is `full` whole, or its first words followed by an ellipsis: the
// cut falls where a word of `full` ends, never inside one (or a number).
::testing::AssertionResult shortened_by_words(const std::string& shown, const std::string& full) {
  if (shown == full) return ::testing::AssertionSuccess();
  const std::string more = "\u2026";
  if (shown.size() < more.size() || shown.compare(shown.size() - more.size(), more.size(), more) != 0)
    return ::testing::AssertionFailure() << "'" << shown << "' is cut without an ellipsis from '" << full << "'";
  const std::string head = shown.substr(0, shown.size() - more.size());
  if (full.compare(0, head.size(), head) != 0)
    return ::testing::AssertionFailure() << "'" << shown << "' is not the start of '" << full << "'";
  const char next = full[head.size()];
  if (next != ' ' && next != ',' && next != ';' && next != ':')
    return ::testing::AssertionFailure() << "'" << shown << "' cuts '" << full << "' inside a word";
  return ::testing::AssertionSuccess();
}

// The console started in t, its parameter panel drawn (the screen in s).
::testing::AssertionResult ready(const Tmux& t, std::string& s) {
  if (!t.started()) return ::testing::AssertionFailure() << t.error();
  if (!t.wait_for(panel_read, s)) return ::testing::AssertionFailure() << "no parameter panel:\n" << s;
  return ::testing::AssertionSuccess();
}

// `keys` sent, the console gone (its exit status on the pane).
::testing::AssertionResult quit(const Tmux& t, const std::string& keys, std::string& s) {
  t.keys(keys);
  if (!t.wait_for([](const std::string& x) { return contains(x, "EXIT="); }, s))
    return ::testing::AssertionFailure() << keys << " did not quit:\n" << s;
  return ::testing::AssertionSuccess();
}

// body(t, s, z) at each size in turn, on the console started with
// args_for(z) in t, its panel drawn (the screen in s).
using Body = std::function<void(const Tmux&, std::string&, const Size&)>;
void at_each_size(const std::function<std::string(const Size&)>& args_for, const Body& body) {
  for (const Size& z : kSizes) {
    SCOPED_TRACE(size_name(z));
    Tmux t = console_in(args_for(z), z.cols, z.rows);
    std::string s;
    ASSERT_TRUE(ready(t, s));
    body(t, s, z);
    if (::testing::Test::HasFatalFailure()) return;
  }
}
void at_each_size(const std::string& args, const Body& body) {
  at_each_size([&](const Size&) { return args; }, body);
}

TEST(ConsoleTuiText, AnEditReplacesTheValueOnTheFirstKeyAndTheArrowsKeepIt) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  at_each_size("--sim hasel --no-record", [](const Tmux& t, std::string& s, const Size& z) {
    // F2, Down to Lambda, Enter: the edit opens on the value in force and
    // the line under the panel says what a key does to it.
    t.keys("F2 Down Enter");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "typing replaces"); }, s)) << s;
    EXPECT_TRUE(contains(s, "= 1 1 1 1 1 1")) << s;  // on 80 columns the name scrolls off
    t.keys("5 Enter");
    ASSERT_TRUE(t.wait_for([&](const std::string& x) { return contains(value_row(x, "Lambda", z), "5 5 5 5 5 5"); }, s))
        << s;
    EXPECT_FALSE(contains(s, "15")) << "the 5 was appended to the old value\n" << s;
    // An arrow (End) keeps the value to edit: Backspace then drops one
    // character, and the hint says how the edit ends.
    t.keys("Enter End");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "Enter takes it"); }, s)) << s;
    t.keys("BSpace 2 Enter");
    ASSERT_TRUE(t.wait_for([&](const std::string& x) { return contains(value_row(x, "Lambda", z), "5 5 5 5 5 2"); }, s))
        << s;
    ASSERT_TRUE(quit(t, "q", s));
  });
}

TEST(ConsoleTuiText, QuittingARunUnderNoRecordDoesNotPromiseToKeepIt) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  at_each_size("--sim hasel --no-record", [](const Tmux& t, std::string& s, const Size&) {
    t.keys("F5");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "RUNNING"); }, s)) << s;
    t.keys("q");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stop it and quit?"); }, s)) << s;
    EXPECT_TRUE(contains(s, "nothing is kept (--no-record)")) << s;
    EXPECT_FALSE(contains(s, "kept in the database")) << s;
    t.keys("y");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "EXIT="); }, s)) << s;
    EXPECT_TRUE(contains(s, "1 run this session, not kept (--no-record)")) << s;
  });
}

// Every field of the status bar is whole: the bar drops fields, it never
// shows part of one.
::testing::AssertionResult whole_status_fields(const std::string& bar) {
  static const std::vector<std::regex> kFields = {
      std::regex("(link up|link silent|LINK DOWN) /dev/pts/[0-9]+"), std::regex("[0-9.]+[kM]? fr/s [0-9.]+[kM]?B/s"),
      std::regex("crc [0-9]+ err [0-9]+"), std::regex("lost [0-9]+"), std::regex("loop [0-9]+\\.[0-9] Hz"),
      std::regex("step [0-9]+ us \\(max [0-9]+\\)"), std::regex("retries [0-9]+ timeouts [0-9]+"),
      std::regex("fw dropped [0-9]+ overruns [0-9]+"), std::regex("reconnects [0-9]+")};
  std::string rest = trimmed(bar) + " | ";
  for (size_t bar_at; (bar_at = rest.find(" | ")) != std::string::npos; rest.erase(0, bar_at + 3)) {
    const std::string field = rest.substr(0, bar_at);
    bool known = false;
    for (const std::regex& r : kFields) known = known || std::regex_match(field, r);
    if (!known) return ::testing::AssertionFailure() << "'" << field << "' is not a whole field of '" << bar << "'";
  }
  return ::testing::AssertionSuccess();
}

TEST(ConsoleTuiText, LongTextIsShortenedByWordsAndPathsByTheirMiddle) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  // A database deep enough that the title cannot hold its path.
  std::string deep = dir.file("a-folder-with-a-long-name-for-the-recordings-of-this-lab");
  deep += "/and-another-one-below-it-for-this-week";
  ASSERT_EQ(run_process("mkdir -p " + shell_quote(deep)).code, 0);
  auto db = [&](const Size& z) { return deep + "/runs-" + size_name(z) + ".db"; };
  at_each_size([&](const Size& z) { return "--sim hasel --db " + shell_quote(db(z)); },
               [&](const Tmux& t, std::string& s, const Size& z) {
    t.keys("F5");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "RUNNING"); }, s)) << s;
    std::this_thread::sleep_for(std::chrono::milliseconds(800));  // the legend reads out values
    s = t.screen();
    std::vector<std::string> lines = screen_lines(s);
    ASSERT_EQ(lines.size(), size_t(z.rows)) << s;
    // The title: the database's file name stays, its middle folders go.
    EXPECT_TRUE(contains(lines[0], "\u2026/runs-" + size_name(z) + ".db")) << lines[0];
    EXPECT_TRUE(whole_status_fields(lines[size_t(z.rows - 2)]));
    // The plot's legend: a value is shown whole or not at all (%.4g never
    // ends in a point).
    const std::string legend = line_with(s, "y0  ");
    ASSERT_FALSE(legend.empty()) << s;
    EXPECT_FALSE(std::regex_search(legend, std::regex("[0-9]\\.(\\s|$)"))) << legend;

    t.keys("F6");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stopped:"); }, s)) << s;
    // The message as said, whole, from the session log beside the database.
    const std::string log = run_process("cat " + shell_quote(deep + "/runs-" + size_name(z) + ".session.log")).output;
    const size_t at = log.find("run 1 stopped: ");
    ASSERT_NE(at, std::string::npos) << log;
    const std::string said = log.substr(at, log.find('\n', at) - at);
    lines = screen_lines(s);
    EXPECT_TRUE(shortened_by_words(trimmed(lines[size_t(z.rows - 3)]), said));
    // F9: every message whole, wrapped under its time.
    t.keys("F9");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " Messages ("); }, s)) << s;
    std::string pane;  // the pane's text, its rows joined
    for (const std::string& l : screen_lines(s)) {
      const size_t bar = l.find("\u2502");
      if (bar != std::string::npos) pane += " " + trimmed(l.substr(bar + 3));
    }
    std::istringstream each(said);
    for (std::string w; each >> w;) EXPECT_TRUE(contains(pane, w)) << "'" << w << "' of '" << said << "'\n" << s;
    ASSERT_TRUE(quit(t, "q", s));
  });
}

// The help over an 80x24 terminal: no letter of the message or status row
// beside it, on its first page or after PgDn; on 120x40 the columns either
// side of it are blank too.
TEST(ConsoleTuiText, TheHelpLeavesNothingBesideIt) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  at_each_size("--sim hasel --no-record", [](const Tmux& t, std::string& s, const Size& z) {
    for (const char* keys : {"?", "PageDown"}) {
      t.keys(keys);
      ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "Parameters:") || contains(x, "-- lines "); },
                             s))
          << s;
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      s = t.screen();
      const std::vector<std::string> lines = screen_lines(s);
      ASSERT_EQ(lines.size(), size_t(z.rows)) << s;
      // The box, as the console centres it: every row it covers (the help
      // is taller than either terminal, so all but the key bar's) is blank
      // left of it and ends inside it.
      const int w = std::min(z.cols - 2, 100), x0 = (z.cols - w) / 2;
      for (int r = 1; r < z.rows - 1; ++r) {
        const std::string& row = lines[size_t(r)];
        EXPECT_EQ(row.substr(0, size_t(x0)).find_first_not_of(' '), std::string::npos)
            << keys << ", row " << r << ": '" << row << "'\n" << s;
        EXPECT_LE(columns(row), x0 + w) << keys << ", row " << r << ": '" << row << "'\n" << s;
      }
    }
    ASSERT_TRUE(quit(t, "Escape q", s));
  });
}

// F4, Enter on an identification run: what it is, its loop named for a
// --sim-fast simulator, and no tracking figure (it has no reference).
TEST(ConsoleTuiText, TheRunsPanelShowsNoTrackingFiguresForAnIdentificationRun) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string db = dir.file("runs.db");
  const auto rec = run_process("env NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN " " + std::string(NLSOFT_CONSOLE_BIN) +
                               " ident --sim hasel --signal prbs --duration 5s --sim-fast --db " + shell_quote(db));
  ASSERT_EQ(rec.code, 0) << rec.output;
  at_each_size("--sim hasel --db " + shell_quote(db), [](const Tmux& t, std::string& s, const Size&) {
    t.keys("F4");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " Runs (1)"); }, s)) << s;
    t.keys("Enter");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "identification run"); }, s)) << s;
    EXPECT_TRUE(contains(s, "loop 130 Hz set")) << s;
    EXPECT_FALSE(contains(s, "nrmse")) << s;
    EXPECT_FALSE(contains(s, "rmse [")) << s;
    ASSERT_TRUE(quit(t, "q", s));
  });
}

// The side panel's text right of its border on the row holding `what`
// ("" if no row does), its trailing blanks dropped.
std::string panel_text(const std::string& screen, const std::string& what) {
  const std::string row = line_with(screen, what);
  const size_t bar = row.rfind("\u2502");
  const std::string text = bar == std::string::npos ? row : row.substr(bar + 3);
  const size_t end = text.find_last_not_of(' ');
  return end == std::string::npos ? "" : text.substr(0, end + 1);
}

// `shown` is the key hints `full` whole, or its first hints whole followed
// by " ..." (an ellipsis): never a hint cut inside ("A r", "R re").
::testing::AssertionResult hints_whole(const std::string& shown, const std::string& full) {
  if (shown == full) return ::testing::AssertionSuccess();
  const std::string tail = " \u2026";
  if (shown.size() < tail.size() || shown.compare(shown.size() - tail.size(), tail.size(), tail) != 0)
    return ::testing::AssertionFailure() << "'" << shown << "' is cut without an ellipsis from '" << full << "'";
  const std::string head = shown.substr(0, shown.size() - tail.size());
  if (full.compare(0, head.size(), head) != 0 || full.compare(head.size(), 2, "  ") != 0)
    return ::testing::AssertionFailure() << "'" << shown << "' cuts a hint of '" << full << "'";
  return ::testing::AssertionSuccess();
}

// Each panel's key hints and the reference panel's "in force" line are whole
// or cut between words with an ellipsis; the parameter details keep the
// range whole (the description gives way, ending in an ellipsis); an edit
// opens on a whole word, not inside the label; and at 80x24 the quit dialog
// leaves no letter or border of the screen beside it (it left a `y` in
// column 0 and a border's end in column 79).
TEST(ConsoleTuiText, PanelHintsDetailsEditsAndTheQuitDialogAreCutBetweenWords) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  at_each_size("--sim hasel --no-record", [](const Tmux& t, std::string& s, const Size& z) {
    t.keys("F2");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "Q: tracking weight"); }, s)) << s;
    const std::string params = panel_text(s, z.cols < 100 ? "Enter u S L R A" : "Enter edit");
    EXPECT_TRUE(z.cols < 100 ? params == "Enter u S L R A (F1)" || hints_whole(params, "Enter u S L R A (F1)")
                             : hints_whole(params, "Enter edit  u undo  S/L save/load  R reread  A reapply"))
        << params << "\n" << s;
    // Q's details: the range line whole ("... 3 values (one sets all)"); a
    // description that does not fit ends in an ellipsis.
    std::string pane;  // the panel's rows joined
    for (const std::string& l : screen_lines(s)) pane += " " + trimmed(panel_text(l, "\u2502"));
    EXPECT_TRUE(contains(pane, "range [0, 1e+12] 1/y^2, 3 values (one sets all)")) << s;
    std::vector<std::string> details;
    bool in = false;
    for (const std::string& l : screen_lines(s)) {
      const std::string p = panel_text(l, "\u2502");
      if (contains(p, "Q: tracking weight")) in = true;
      if (in && contains(p, "range [")) break;
      if (in) details.push_back(p);
    }
    ASSERT_FALSE(details.empty()) << s;
    std::string joined;
    for (const std::string& d : details) joined += (joined.empty() ? "" : " ") + trimmed(d);
    EXPECT_TRUE(shortened_by_words(joined, "Q: tracking weight per output (diagonal of Q): larger follows the "
                                           "reference harder"))
        << s;
    // Lambda's edit: a whole word first, never the label's tail ("bda =").
    t.keys("Down Enter");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "typing replaces"); }, s)) << s;
    const std::string edit = value_row(s, "Lambda", z);
    EXPECT_TRUE(std::regex_search(edit, std::regex("Lambda +(Lambda = |= )1 1 1 1 1 1"))) << edit << "\n" << s;
    t.keys("Escape F3");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "in force:"); }, s)) << s;
    const std::string force = trimmed(panel_text(s, "in force:"));
    EXPECT_TRUE(shortened_by_words(force, "in force: swirl (the firmware's own)")) << force << "\n" << s;
    EXPECT_TRUE(hints_whole(panel_text(s, " kind"), "\u2190\u2192 kind  Enter edit  a send/upload")) << s;
    t.keys("F4");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "Enter metrics"); }, s)) << s;
    EXPECT_TRUE(hints_whole(panel_text(s, "Enter metrics"), "Enter metrics  m mark  c compare  e export  R reread"))
        << s;
    // The quit dialog over a run: on every row of it and its margin, the
    // first and the last column blank.
    t.keys("F5");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "RUNNING"); }, s)) << s;
    t.keys("q");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stop it and quit?"); }, s)) << s;
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // redraws with the plot moving under it
    s = t.screen();
    const std::vector<std::string> lines = screen_lines(s);
    size_t top = lines.size(), bottom = 0;
    for (size_t i = 0; i < lines.size(); ++i) {
      if (contains(lines[i], "stop it and quit?")) top = i;
      if (contains(lines[i], "y: yes")) bottom = i;
    }
    ASSERT_LT(top, bottom) << s;
    // (Wider, the dialog leaves columns of the plot and the panel either
    // side: only a margin of one or two would be a stray letter.)
    for (size_t r = top - 1; z.cols < 100 && r <= bottom + 1 && r < lines.size(); ++r) {
      const std::string& row = lines[r];
      EXPECT_TRUE(row.empty() || row[0] == ' ') << "row " << r << ": '" << row << "'\n" << s;
      EXPECT_TRUE(columns(row) < z.cols) << "row " << r << " reaches the last column: '" << row << "'\n" << s;
    }
    ASSERT_TRUE(quit(t, "y", s));
  });
}

TEST(ConsoleProgressBar, AnEtaOnlyWhileThereIsSomethingLeftToCount) {
  EXPECT_EQ(ProgressBar::tail(0.5, 10.0), " 50%  ETA   10s ");
  EXPECT_EQ(ProgressBar::tail(1.0, 10.0), "100%  ") << "a build linking at 100 % once showed ETA 0s";
  EXPECT_EQ(ProgressBar::tail(0.0, 10.0), "  0%  ");
}

// `ident` on a terminal: its progress bar and the firmware's message that
// the run is over ("firmware info: identification run finished ...") each
// get a line; the message never lands after the bar's "ETA 0s".
TEST(ConsoleTuiText, AMessageDuringAProgressBarGetsALineOfItsOwn) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  for (const Size& z : kSizes) {
    SCOPED_TRACE(size_name(z));
    Tmux t = console_in("ident --sim hasel --signal prbs --duration 30s --sim-fast --db " +
                            shell_quote(dir.file("ident-" + size_name(z) + ".db")),
                        z.cols, z.rows);
    ASSERT_TRUE(t.started()) << t.error();
    std::string s;
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "EXIT="); }, s, 60)) << s;
    EXPECT_EQ(quit_status(s), "EXIT=0") << s;
    const std::string said = line_with(s, "identification run finished");
    ASSERT_FALSE(said.empty()) << s;
    EXPECT_EQ(said.rfind("firmware info: ", 0), 0u) << "'" << said << "'\n" << s;
    EXPECT_FALSE(contains(s, "ETA")) << "the bar is cleared once the run is over\n" << s;
  }
}

}  // namespace
}  // namespace nlsoft::console
