// `tune` against the simulated firmware (--sim-fast): from a deliberately
// bad tuning it finds one that tracks no worse than the shipped preset
// within 40 runs, on HASEL and on the tendon rig; the session is recorded,
// grouped and plotted; bad input is a usage error; --help's example runs;
// Ctrl-C keeps the best.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "app/record/run_metrics.hpp"
#include "app/record/run_store.hpp"
#include "app/record/tune_log.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;
using nlsoft::test::slurp;

using test::run_process;
using test::shell_quote;

class TuneE2E : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }
  test::ProcessResult console(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args);
  }
  test::ProcessResult script(const std::string& platform, const std::string& text) const {
    const std::string file = dir_.file("tune.nls");
    std::ofstream(file) << text;
    return console("--sim " + platform + " --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(file));
  }
  std::string db() const { return dir_.file("runs.db"); }

  // The proof: the preset's tracking over the window every evaluation is
  // scored on (the whole Swirl; three runs, their mean), then a bad start
  // (Q a hundredth of the preset's, Lambda far too high for the rig), then
  // tune over Lambda and a factor on Q.
  void tuned_reaches_the_preset(const std::string& platform, const std::string& bad_lambda, const std::string& bad_q) {
    const std::string best = dir_.file("best.params");
    const auto r = script(platform,
                          "ref swirl hold=1\n"
                          "sweep Lambda 1 1 1 run 9s settle=500ms label=preset\n"
                          "set Lambda " + bad_lambda + "\n"
                          "set Q " + bad_q + "\n"
                          "tune Lambda=0.01..1e10:log Q*=0.01..1e4:log budget=40 settle=500ms window=9s save=" + best + "\n"
                          "get Lambda\n");
    ASSERT_EQ(r.code, 0) << r.output;
    std::printf("%s\n", r.output.c_str());
    RunStore store(db());
    const auto runs = store.list();
    ASSERT_GE(runs.size(), 4u);
    double preset = 0;
    for (int i = 0; i < 3; ++i) {
      ASSERT_EQ(runs[size_t(i)].label, "preset");
      preset += run_metrics(store, runs[size_t(i)].id, 0.5, 9.0).truth.nrmse / 3;
    }
    const auto sessions = tune_sessions(db());
    ASSERT_EQ(sessions.size(), 1u);
    ASSERT_GT(sessions[0].best_run, 0) << r.output;
    const auto evals = tune_evals(db(), sessions[0].id);
    ASSERT_FALSE(evals.empty());
    EXPECT_LE(evals.size(), 40u);
    ASSERT_TRUE(evals[0].objective) << "the bad start is a run that tracks, just badly: " << evals[0].failed;
    const double start = *evals[0].objective;
    const double tuned = run_metrics(store, sessions[0].best_run, 0.5, 9.0).truth.nrmse;
    int used = 0;
    for (const auto& e : evals)
      if (e.run_id == sessions[0].best_run) used = e.eval;
    std::printf("%s: start nrmse %.4f, preset %.4f, tuned %.4f at evaluation %d of %zu\n", platform.c_str(), start,
                preset, tuned, used, evals.size());
    EXPECT_GT(start, 1.5 * preset) << "the start must be clearly worse than the preset for the test to mean anything";
    EXPECT_LE(tuned, preset) << r.output;
    // The best set went through `params save`; the parameters are back as
    // they were (no apply).
    EXPECT_TRUE(contains(slurp(best), "Lambda ")) << slurp(best);
    EXPECT_TRUE(contains(r.output, "Lambda = " + bad_lambda_echo(bad_lambda))) << r.output;
  }

  static std::string bad_lambda_echo(const std::string& v) { return v == "1e8" ? "1e+08" : v == "1e5" ? "100000" : v; }

  test::TempDir dir_;
};

TEST_F(TuneE2E, HaselFromABadTuningTracksAsWellAsThePresetWithin40Runs) {
  tuned_reaches_the_preset("hasel", "1e8", "1e4 2e4 1e4");
}

TEST_F(TuneE2E, TendonFromABadTuningTracksAsWellAsThePresetWithin40Runs) {
  tuned_reaches_the_preset("tendon", "1e5", "1e-5 50 20");
}

// The example --help gives is run as written, with a database and a file
// of its own; its session is then grouped by runs list and plotted.
TEST_F(TuneE2E, HelpTeachesWithAnExampleThatRunsAndIsGroupedAndPlotted) {
  const auto help = console("tune --help");
  ASSERT_EQ(help.code, 0) << help.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(help.output, m, std::regex(R"(\n  (nlsoft-console tune [^\n]*\\\n[^\n]*)\n)")))
      << help.output;
  std::string example = std::regex_replace(m[1].str(), std::regex(R"(\\\n\s*)"), "");
  example.replace(0, std::string("nlsoft-console").size(), NLSOFT_CONSOLE_BIN);
  const std::string saved = dir_.file("example.params");
  const auto r = run_process(example + " --db " + shell_quote(db()) + " --save " + shell_quote(saved));
  ASSERT_EQ(r.code, 0) << example << "\n" << r.output;
  EXPECT_TRUE(contains(r.output, "tuning session 1: minimise")) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex(R"(eval 1/\d+: Lambda=)"))) << r.output;
  EXPECT_TRUE(contains(r.output, "best: ")) << r.output;
  EXPECT_TRUE(contains(slurp(saved), "Q ")) << slurp(saved);

  const auto list = console("runs list --db " + shell_quote(db()));
  ASSERT_EQ(list.code, 0) << list.output;
  EXPECT_TRUE(contains(list.output, "tuning session 1: minimise nrmse + 0.1*u_effort")) << list.output;
  EXPECT_TRUE(contains(list.output, "(best)")) << list.output;
  EXPECT_TRUE(std::regex_search(list.output, std::regex(R"(\n\s+1\s{4}\d{4}-)"))) << "runs indented under it: "
                                                                                    << list.output;
  if (run_process("command -v gnuplot").code != 0) GTEST_SKIP() << "gnuplot is not installed: runs plot needs it";
  const std::string svg = dir_.file("t.svg");
  const auto plot = console("runs plot --tune 1 --svg " + shell_quote(svg) + " --db " + shell_quote(db()));
  ASSERT_EQ(plot.code, 0) << plot.output;
  const std::string image = slurp(svg);
  EXPECT_TRUE(contains(image, "<svg")) << image.substr(0, 200);
  EXPECT_TRUE(contains(image, "best so far"));
  EXPECT_EQ(console("runs plot --tune 9 --svg " + shell_quote(svg) + " --db " + shell_quote(db())).code, 2);
}

TEST_F(TuneE2E, BadInputIsAUsageErrorInWords) {
  const std::string base = "tune --sim hasel --sim-fast --no-record ";
  struct Case {
    std::string args, says;
  };
  for (const Case& c : std::vector<Case>{
           {"--param Lambda=5..1", "LO must be below HI"},
           {"--param Lambda=0..1:log", "LO > 0"},
           {"--param Lambda=1..2 --objective \"nrmse +\"", "column"},
           {"--param Lambda=1..2 --objective bogus", "unknown metric 'bogus'"},
           {"--param Lambda=1..2 --budget soon", "budget 'soon'"},
           {"--param Colour=1..2", "Colour"},
           {"--param Q7=1..2", "Q[7]"},
           {"--param Lambda=1..1e13:log", "outside Lambda's range"},
           {"--param Lambda=1..2 --param Lambda=3..4", "already searched"},
           {"--param Lambda=1..2 --budget 0s", "a time budget must be positive"},
           {"--param Lambda=1..2:lg", "':lg' is not a scale; use :log or :lin"},
       }) {
    const auto r = console(base + c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, c.says)) << c.args << "\n" << r.output;
  }
  const auto none = console("tune --param Lambda=1..2");
  EXPECT_EQ(none.code, 2);
  EXPECT_TRUE(contains(none.output, "nothing to connect to")) << none.output;
}

// Inputs sitting at a limit beyond the stated share fail the evaluation,
// whatever its tracking: with a share of 0 every run fails (HASEL starts
// from neutral, its lower limit), nothing is saved and the exit is 1.
TEST_F(TuneE2E, ARunThatSaturatesScoresAsFailedNeverAsGood) {
  const auto r = console("tune --sim hasel --sim-fast --no-record --param Lambda=0.1..10:log --budget 3 --settle 0 "
                         "--window 300ms --max-saturated 0 --save " + shell_quote(dir_.file("none.params")));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "FAILED: u at a limit")) << r.output;
  EXPECT_TRUE(contains(r.output, "no evaluation succeeded: nothing saved")) << r.output;
  EXPECT_FALSE(std::ifstream(dir_.file("none.params")).good());
}

// From a script: apply leaves the best in force (get reads it back, the
// saved file has it); a candidate the firmware's cross-parameter rules
// refuse (Nc > N) scores as failed, with the firmware's reason, and is
// never applied. (Inside the build's capacity, Nc <= max_nc = 4, which a
// range must keep to: beyond it the range is refused before any run.)
TEST_F(TuneE2E, ApplyLeavesTheBestInForceAndRefusedCandidatesFail) {
  const std::string saved = dir_.file("applied.params");
  const auto r = script("hasel",
                        "ref swirl hold=1\n"
                        "set Lambda 1e8\n"
                        "tune Lambda=0.01..1e10:log budget=6 settle=500ms window=9s apply save=" + saved + "\n"
                        "get Lambda\n"
                        "get N\n"
                        "set N 2\n"
                        "tune Nc=3..4 budget=2 settle=0 window=1s\n"
                        "get Nc\n");
  EXPECT_EQ(r.code, 1) << "the second session found nothing: the script fails\n" << r.output;
  EXPECT_TRUE(contains(r.output, "it is in force now (apply)")) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(\nLambda = ([0-9.e+]+) [^\n]*1/u\^2)"))) << r.output;
  EXPECT_NE(m[1].str(), "1e+08") << "the best, not the start, is in force\n" << r.output;
  EXPECT_TRUE(contains(slurp(saved), "Lambda " + m[1].str())) << slurp(saved) << r.output;
  EXPECT_TRUE(contains(r.output, "N = 3")) << r.output;
  EXPECT_TRUE(contains(r.output, "Nc is 1, outside 3..4; the search starts at 3")) << r.output;
  EXPECT_TRUE(contains(r.output, "FAILED: the firmware refused it")) << r.output;
  EXPECT_TRUE(contains(r.output, "Nc = 1")) << "the refused values never stayed\n" << r.output;
  EXPECT_TRUE(contains(r.output, "0 expects held, 0 failed; 1 tuning session found nothing")) << r.output;
}

// The defaults (settle 1 s, window 5 s) on the rig's start-up Swirl (hold
// 10) see its flat start only: the session says so after the first run and
// what to change; the same session over the whole Swirl at hold=1 does not.
TEST_F(TuneE2E, AWindowWhereTheReferenceBarelyMovesIsWarnedAbout) {
  auto r = console("tune --sim hasel --sim-fast --no-record --param 'Lambda=0.5..2:log' --budget 2 --save " +
                   shell_quote(dir_.file("still.params")));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "warning: the reference barely moves in the scored window (1 s to 6 s of each run)"))
      << r.output;
  EXPECT_TRUE(contains(r.output, "--reference \"swirl hold=1\"")) << r.output;
  r = console("tune --sim hasel --sim-fast --no-record --param 'Lambda=0.5..2:log' --budget 2 --reference 'swirl "
              "hold=1' --settle 500ms --window 9s --save " + shell_quote(dir_.file("moving.params")));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "best: ")) << r.output;
  EXPECT_FALSE(contains(r.output, "barely moves")) << r.output;
}

// One run is one run: the budget and the end say it in the singular.
TEST_F(TuneE2E, ABudgetOfOneRunSaysOneRun) {
  const auto r = console("tune --sim hasel --sim-fast --no-record --param 'Lambda=0.5..2:lin' --budget 1 --reference "
                         "'swirl hold=1' --settle 0 --window 2s --save " + shell_quote(dir_.file("one.params")));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "budget 1 run;")) << r.output;
  EXPECT_TRUE(contains(r.output, "ended: budget of 1 run used")) << r.output;
  EXPECT_FALSE(contains(r.output, "1 runs")) << r.output;
}

// A wall-time budget alone: as many runs as fit, then the session ends
// saying so, with its best saved. In real time: the first run's 2 s of
// control steps cannot take less than 2 s, past the 1 s budget.
TEST_F(TuneE2E, ATimeBudgetEndsTheSession) {
  const auto r = console("tune --sim hasel --no-record --param Lambda=0.01..1e10:log --budget \"1 s\" "
                         "--reference 'swirl hold=1' --settle 0 --window 2s --save " + shell_quote(dir_.file("t.params")));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "budget 1 s;")) << r.output;
  EXPECT_TRUE(contains(r.output, "ended: time budget of 1 s used")) << r.output;
  EXPECT_TRUE(contains(slurp(dir_.file("t.params")), "Lambda ")) << r.output;
}

// Ctrl-C once the second evaluation has been reported: the run in progress
// is stopped and kept, the session ends, the best so far is printed and
// saved, exit 0. In real time (no --sim-fast), so 40 runs of 2 s cannot all
// be over before the signal comes.
TEST_F(TuneE2E, CtrlCStopsAndKeepsTheBest) {
  const std::string out = dir_.file("out.txt"), saved = dir_.file("kept.params");
  const std::string cmd = std::string(NLSOFT_CONSOLE_BIN) +
                          " tune --sim hasel --param Lambda=0.01..100:log --budget 40 --settle 0 --window 1s"
                          " --reference 'swirl hold=1' --db " + shell_quote(db()) + " --save " + shell_quote(saved);
  const auto r = run_process("(" + cmd + " > " + shell_quote(out) + " 2>&1 & p=$!; i=0; " +
                             "while ! grep -q 'eval 2/' " + shell_quote(out) + " && [ $i -lt 1200 ]; do sleep 0.1; i=$((i+1)); done; " +
                             "kill -INT $p; wait $p; echo exit=$?)");
  const std::string text = slurp(out);
  EXPECT_TRUE(contains(r.output, "exit=0")) << r.output << text;
  EXPECT_TRUE(contains(text, "ended: interrupted (Ctrl-C)")) << text;
  EXPECT_TRUE(contains(text, "best: ")) << text;
  EXPECT_TRUE(contains(slurp(saved), "Lambda ")) << text;
  const auto sessions = tune_sessions(db());
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].end_reason, "interrupted (Ctrl-C)");
}

}  // namespace
}  // namespace nlsoft::console
