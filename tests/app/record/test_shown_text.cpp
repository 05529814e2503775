// Text that came from a user, a shared database or a file, shown back on a
// terminal: labels are capped (a 100,000-character label is refused, not a
// 100,085-column row), and control characters are shown as escapes in
// `runs list`/`show`/`compare` and in errors quoting a bad CSV cell, so
// nothing stored can move the cursor or recolour the screen.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>

#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;

using test::run_process;
using test::shell_quote;

bool has_control(const std::string& s) {
  for (char c : s)
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\n') || c == 0x7f) return true;
  return false;
}

class ShownText : public ::testing::Test {
 protected:
  void SetUp() override {
    ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
    Recorder rec(db());
    for (int i = 0; i < 2; ++i) {
      RunInfo ri;
      ri.platform = "msd";
      ri.n = 1;
      ri.m = 1;
      // What someone else's console (or sqlite3 shell) may have stored.
      ri.notes = "line one\nline two\x1b[2J";
      ri.params = {{"Q\x1b[31m", "1\r2"}};
      const int64_t id = rec.begin_run(ri);
      rec.end_run(id, "completed\x1b]0;title\x07", 0, 0);
    }
  }
  test::ProcessResult console(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args);
  }
  test::ProcessResult runs(const std::string& args) const { return console("runs " + args + " --db " + shell_quote(db())); }
  std::string db() const { return dir_.file("runs.db"); }
  test::TempDir dir_;
};

TEST_F(ShownText, ALabelLongerThanTwoHundredCharactersIsRefused) {
  auto r = runs("label 1 " + shell_quote(std::string(100000, 'x')));
  EXPECT_EQ(r.code, 2) << r.output.substr(0, 300);
  EXPECT_TRUE(contains(r.output, "a label is at most 200 characters; this one has 100000")) << r.output.substr(0, 300);
  EXPECT_LT(r.output.size(), 500u) << "the refusal does not echo the label";
  EXPECT_EQ(RunStore(db()).run(1).label, "") << "nothing stored";

  // 200 characters (UTF-8: characters, not bytes) are a label.
  std::string accents;
  for (int i = 0; i < 200; ++i) accents += "\xc3\xa9";
  r = runs("label 1 " + shell_quote(accents));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(RunStore(db()).run(1).label, accents);

  // A script's run label is held to the same.
  std::ofstream(dir_.file("s.nls")) << "run 1s label=" << std::string(201, 'y') << "\n";
  r = console("--sim msd --db " + shell_quote(db()) + " --script " + shell_quote(dir_.file("s.nls")));
  EXPECT_EQ(r.code, 2) << r.output.substr(0, 500);
  EXPECT_TRUE(contains(r.output, "a label is at most 200 characters; this one has 201")) << r.output.substr(0, 500);
  EXPECT_EQ(RunStore(db()).list().size(), 2u) << "no run was started";
}

TEST_F(ShownText, ControlCharactersFromTheDatabaseAreShownEscaped) {
  auto r = runs("label 2 " + shell_quote("evil\n\x1b[31mred"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(has_control(r.output)) << r.output;
  EXPECT_EQ(RunStore(db()).run(2).label, "evil\n\x1b[31mred") << "stored as given";

  r = runs("list");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "evil\\n\\x1b[31mred")) << r.output;
  // The ended column keeps a word or two; `runs show` has the whole reason.
  EXPECT_TRUE(contains(r.output, "completed\\x1b")) << r.output;
  EXPECT_FALSE(has_control(r.output)) << r.output;

  r = runs("show 2");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "\"evil\\n\\x1b[31mred\"")) << r.output;
  EXPECT_TRUE(contains(r.output, "completed\\x1b]0;title\\x07")) << r.output;
  EXPECT_TRUE(contains(r.output, "notes: line one\\nline two\\x1b[2J")) << r.output;
  EXPECT_TRUE(contains(r.output, "Q\\x1b[31m")) << r.output;
  EXPECT_FALSE(has_control(r.output)) << r.output;

  r = runs("compare 1 2");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(has_control(r.output)) << r.output;

  // --json stays exact: JSON escapes control characters itself.
  r = runs("show 2 --json");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "\"evil\\n\\u001b[31mred\"")) << r.output;
}

TEST_F(ShownText, ErrorsQuoteABadCsvCellEscaped) {
  std::ofstream(dir_.file("ref.csv")) << "0.1\n0.2\x1b[31m\n";
  std::ofstream(dir_.file("s.nls")) << "ref load " << dir_.file("ref.csv") << "\n";
  auto r = console("--sim msd --db " + shell_quote(db()) + " --script " + shell_quote(dir_.file("s.nls")));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "'0.2\\x1b[31m' is not a number")) << r.output;
  EXPECT_FALSE(has_control(r.output)) << r.output;

  std::ofstream(dir_.file("data.csv")) << "u0,y0\n1,2\n3,\x1b[2J" << std::string(500, 'z') << "\n";
  r = console("train --platform msd --data " + shell_quote(dir_.file("data.csv")) + " --out " +
              shell_quote(dir_.file("m.nlsm")));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "\\x1b[2Jzzz")) << r.output;
  EXPECT_FALSE(has_control(r.output)) << r.output;
  EXPECT_LT(r.output.size(), 400u) << "a long cell is cut in the message: " << r.output;
}

}  // namespace
}  // namespace nlsoft::console
