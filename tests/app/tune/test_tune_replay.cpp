// `tune --replay N` on runs a real console session recorded against
// nlsoft-firmware-sim: from a recording made with a poor tuning the search
// finds a set whose replay tracks better, the first evaluation is the
// recording again, only the best is recorded; runs that cannot be replayed
// and options that reach for a firmware are refused with nothing written;
// one seed, one search.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "app/record/recorder.hpp"
#include "app/record/run_metrics.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sample.hpp"
#include "app/record/tune_log.hpp"
#include "app/support/board_run.hpp"
#include "app/support/run_process.hpp"
#include "app/support/sim_session_test.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;
using nlsoft::test::slurp;

using test::run_process;
using test::shell_quote;

// The lines of `text` that start with `prefix`.
std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  return out;
}

std::string param_at_start(RunStore& store, int64_t run, const std::string& name) {
  for (const ParamRecord& p : store.params(run))
    if (p.at_start && p.name == name) return p.value;
  return "";
}

using TuneReplay = test::SimSessionTest;

// The constructed case: hasel's whole Swirl recorded with Q a hundredth of
// its default (1e6 2e6 1e6). Tuned on replays of that run, the best set's
// replay tracks clearly better than the recording did, over the same
// window; the search's first evaluation is the recording replayed (the
// same nrmse); the candidates leave no run behind, the best one run of
// kind replay with the saved set's parameters, and no tuning session.
TEST_F(TuneReplay, APoorRecordingIsBeatenOnItsReplays) {
  session("hasel", "ref swirl hold=1\nset Q 1e4 2e4 1e4\nrun 9s label=poor\n");
  const std::string saved = dir_.file("best.params");
  const auto r = console("tune --replay 1 --param 'Q*=0.01..1e4:log' --param 'Lambda=0.01..1e10:log' --db " +
                         shell_quote(db()) + " --save " + shell_quote(saved));
  ASSERT_EQ(r.code, 0) << r.output;
  std::printf("%s\n", r.output.c_str());
  EXPECT_TRUE(contains(r.output, "tuning on replays of run 1: minimise nrmse over Q*=0.01..1e4:log")) << r.output;
  EXPECT_TRUE(contains(r.output, "each evaluation is a replay of run 1 in this process")) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex(R"(\neval 1/40: Q\*=1 Lambda=1 -> )"))) << r.output;
  EXPECT_TRUE(contains(r.output, "not from the rig; over 1 s to ")) << r.output;
  EXPECT_TRUE(contains(r.output, "the best's replay is recorded as run 2 (kind replay)")) << r.output;

  RunStore store(db());
  ASSERT_EQ(store.last_run_id(), 2) << "only the best's replay is recorded\n" << r.output;
  const RunRow best = store.run(2);
  EXPECT_EQ(best.kind, "replay");
  EXPECT_TRUE(contains(best.label, "tune --replay 1: best")) << best.label;
  EXPECT_TRUE(tune_sessions(db()).empty()) << "a replay's search is no session of the rig";

  // Scored as the search scored: from 1 s (--settle's default) to the end.
  const double recorded = run_metrics(store, 1, 1.0, 0).truth.nrmse;
  const double tuned = run_metrics(store, 2, 1.0, 0).truth.nrmse;
  std::printf("recorded nrmse %.4f, tuned on replays %.4f\n", recorded, tuned);
  EXPECT_LT(tuned, 0.9 * recorded) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(start ([0-9.e+-]+)\): )"))) << r.output;
  EXPECT_NEAR(std::stod(m[1].str()), recorded, 1e-5 * recorded) << "the start, replayed, is the recording";
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(\n  nrmse +([0-9.]+) +([0-9.]+)\n)"))) << r.output;
  EXPECT_NEAR(std::stod(m[1].str()), recorded, 1e-4);
  EXPECT_NEAR(std::stod(m[2].str()), tuned, 1e-4);

  // The saved set is the one the best's replay ran, and not the recording's.
  const std::string file = slurp(saved);
  EXPECT_TRUE(contains(file, "\nQ " + param_at_start(store, 2, "Q") + "\n")) << file;
  EXPECT_TRUE(contains(file, "\nLambda " + param_at_start(store, 2, "Lambda") + "\n")) << file;
  EXPECT_NE(param_at_start(store, 2, "Q"), param_at_start(store, 1, "Q"));
}

// Refused, exit 2, nothing recorded and nothing saved: runs `runs replay`
// refuses, options that reach for a firmware (which --replay has none of),
// a window past the run's end, a parameter the simulator has not.
TEST_F(TuneReplay, WhatCannotBeReplayedOrReachesForAFirmwareIsRefusedWithNothingWritten) {
  session("hasel", "ident prbs 2s seed=3\nref swirl hold=1\nrun 3s label=swirl\n");
  // Run 3: a board's run, as a console records one.
  ASSERT_EQ(test::record_a_boards_run(db()), 3);
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"--replay 1", "run 1 is an identification run"},
      {"--replay 3", "run 3 was recorded on nlsoft-f446 0.1.0 (hasel), not on the simulator"},
      {"--replay 9", "no run 9"},
      {"--replay 2 --rig tendon", "run 2 was recorded on rig 'hasel', not on rig 'tendon'"},
      {"--replay 2 --sim hasel", "connects to nothing: leave out --sim"},
      {"--replay 2 --qemu hasel", "leave out --qemu"},
      {"--replay 2 /dev/ttyACM0", "leave out PORT (/dev/ttyACM0)"},
      {"--replay 2 --sim-fast --baud 9600", "leave out --baud, --sim-fast"},
      {"--replay 2 --reference swirl", "--reference selects one on a connected firmware"},
      {"--replay 2 --apply", "--apply leaves the best in force on a connected firmware"},
      {"--replay 2 --window 60s", "run 2 lasts"},
      {"--replay 2 --settle 60s", "leaves nothing of it to score"},
      {"--replay 2 --param Colour=1..2", "Colour"},
      {"--replay 2 --model " + shell_quote(dir_.file("none.nlsm")), "cannot open model file"},
      {"--sim hasel --sim-fast --model " + shell_quote(dir_.file("none.nlsm")), "it goes with --replay N"},
      {"--replay 0", "--replay"},
  };
  const std::string saved = dir_.file("never.params");
  for (const Case& c : cases) {
    const auto r = console("tune " + c.args + " --param 'Lambda=0.1..10:log' --budget 3 --db " + shell_quote(db()) +
                           " --save " + shell_quote(saved));
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, c.message)) << c.args << "\n" << r.output;
  }
  RunStore store(db());
  EXPECT_EQ(store.last_run_id(), 3) << "a refused tune --replay recorded a run";
  EXPECT_TRUE(tune_sessions(db()).empty());
  EXPECT_FALSE(std::ifstream(saved).good()) << "a refused tune --replay saved a set";
}

// A candidate the firmware's cross-parameter rules refuse (Nc > N, run 1
// ran N = 2) fails as on a rig, with the firmware's words; with every
// evaluation failed nothing is saved or recorded, exit 1.
TEST_F(TuneReplay, ACandidateTheFirmwareRefusesFailsAsOnARig) {
  session("hasel", "set N 2\nref swirl hold=1\nrun 2s label=short\n");
  const std::string saved = dir_.file("none.params");
  const auto r = console("tune --replay 1 --param Nc=3..4 --budget 2 --db " + shell_quote(db()) + " --save " +
                         shell_quote(saved));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "Nc is 1, outside 3..4; the search starts at 3")) << r.output;
  EXPECT_TRUE(contains(r.output, "FAILED: the firmware refused it: Nc")) << r.output;
  EXPECT_TRUE(contains(r.output, "no evaluation succeeded: nothing saved, nothing recorded")) << r.output;
  EXPECT_FALSE(std::ifstream(saved).good());
  RunStore store(db());
  EXPECT_EQ(store.last_run_id(), 1);
}

// The same seed, the same search: every evaluation's line and the best,
// twice over, on the same recording; --no-record leaves the database as it
// was.
TEST_F(TuneReplay, OneSeedGivesTheSameSearchTwice) {
  session("hasel", "ref swirl hold=1\nset Lambda 20\nrun 5s label=sluggish\n");
  std::vector<std::string> evals[2], best[2];
  for (int i = 0; i < 2; ++i) {
    const auto r = console("tune --replay 1 --param 'Lambda=0.01..1e4:log' --param 'Q*=0.1..1e3:log' --method "
                           "neldermead --seed 7 --budget 15 --no-record --db " + shell_quote(db()) + " --save " +
                           shell_quote(dir_.file("seed" + std::to_string(i) + ".params")));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "nothing recorded (--no-record)")) << r.output;
    evals[i] = lines_starting(r.output, "eval ");
    best[i] = lines_starting(r.output, "best: ");
  }
  ASSERT_EQ(evals[0].size(), 15u);
  EXPECT_EQ(evals[0], evals[1]);
  ASSERT_EQ(best[0].size(), 1u);
  EXPECT_EQ(best[0], best[1]);
  EXPECT_EQ(slurp(dir_.file("seed0.params")).substr(slurp(dir_.file("seed0.params")).find("\n#") + 1),
            slurp(dir_.file("seed1.params")).substr(slurp(dir_.file("seed1.params")).find("\n#") + 1))
      << "the same set saved (the header's time aside)";
  RunStore store(db());
  EXPECT_EQ(store.last_run_id(), 1);
}

// The nrmse a session's script printed for run `id` ("run 3 (after): ...
// nrmse 1.234 ..."); NaN when it printed none.
double printed_nrmse(const std::string& output, int id) {
  std::smatch m;
  const std::regex line("\nrun " + std::to_string(id) + R"( \([^)]*\): [^\n]* nrmse ([0-9.]+))");
  return std::regex_search(output, m, line) ? std::stod(m[1]) : std::nan("");
}

// In a session's script: a poorly tuned run, then `tune replay=last ...
// apply`. The candidates are replays in the console's process (the
// simulator the session drives runs nothing meanwhile: its only runs are
// the script's own two); the best is loaded onto it as params load would,
// and the run after starts with the best's Q and tracks better than the
// poor one.
TEST_F(TuneReplay, AScriptTunesOnItsLastRunsReplaysAndAppliesTheBest) {
  const std::string script = dir_.file("t.nls"), saved = dir_.file("best.params");
  std::ofstream(script) << "ref swirl hold=1\nset Q 1e4 2e4 1e4\nrun 9s label=poor\n"
                        << "tune replay=last Q*=0.01..1e4:log budget=12 save=" << saved << " apply\n"
                        << "run 9s label=after\n";
  const auto r = console("--sim hasel --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
  ASSERT_EQ(r.code, 0) << r.output;
  std::printf("%s\n", r.output.c_str());
  EXPECT_TRUE(contains(r.output, "tune: run 1 (1170 steps at 130 Hz) replayed per candidate in this process; the "
                                 "firmware is not touched until the best is applied"))
      << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex(R"(loaded onto the firmware \(apply\): Q: )"))) << r.output;

  RunStore store(db());
  ASSERT_EQ(store.last_run_id(), 3) << "the poor run, the best's replay, the run after\n" << r.output;
  EXPECT_EQ(store.run(2).kind, "replay");
  EXPECT_EQ(store.run(3).label, "after");
  const std::string poor_q = param_at_start(store, 1, "Q"), best_q = param_at_start(store, 2, "Q");
  EXPECT_NE(best_q, poor_q);
  EXPECT_EQ(param_at_start(store, 3, "Q"), best_q) << "the run after starts with the best set in force";
  const double poor = printed_nrmse(r.output, 1), after = printed_nrmse(r.output, 3);
  EXPECT_LT(after, 0.9 * poor) << r.output;  // 0.0409 against 0.0518 here
}

// What a script's replay tuning cannot do is refused: reference= beside
// replay= and model= without it before anything runs (the script's check),
// replay=last with no run yet and a run that is not there when the line
// runs, each naming the line.
TEST_F(TuneReplay, AScriptsReplayTuningRefusesWhatItCannotReplay) {
  const auto run_script = [&](const std::string& text) {
    const std::string script = dir_.file("bad.nls");
    std::ofstream(script) << text;
    return console("--sim hasel --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
  };
  struct Case {
    std::string script, says;
  };
  for (const Case& c : std::vector<Case>{
           {"run 1s\ntune replay=1 reference=swirl Lambda=0.01..100:log\n", "replay= replays the run's own reference"},
           {"tune model=m.nlsm Lambda=0.01..100:log\n", "model=FILE names the model the replays run"},
           {"tune replay=0 Lambda=0.01..100:log\n", "replay '0': a recorded run's id (runs list), or last"},
           {"tune replay=last Lambda=0.01..100:log\n", "needs a finished run of this session first"},
           {"run 1s\ntune replay=7 Lambda=0.01..100:log\n", "7"},
       }) {
    const auto r = run_script(c.script);
    EXPECT_NE(r.code, 0) << c.script << r.output;
    EXPECT_TRUE(contains(r.output, c.says)) << c.script << r.output;
    EXPECT_TRUE(contains(r.output, "bad.nls:")) << "the line is named\n" << c.script << r.output;
  }
}

}  // namespace
}  // namespace nlsoft::console
