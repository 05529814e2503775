// `runs replay ID` on runs a real console session recorded against
// nlsoft-firmware-sim: with nothing changed the replay is the recording,
// bit for bit; a change moves the figures the way it must; runs that cannot
// be replayed as they ran are refused by name, and what a replay does not
// repeat is said, never left out silently.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sample.hpp"
#include "app/record/sqlite.hpp"
#include "app/support/board_run.hpp"
#include "app/support/run_process.hpp"
#include "app/support/sim_session_test.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;

using test::run_process;
using test::shell_quote;

class RunsReplay : public test::SimSessionTest {
 protected:
  nlohmann::json compare(int64_t a, int64_t b) const {
    const auto r = console("runs compare " + std::to_string(a) + " " + std::to_string(b) + " --json --db " +
                           shell_quote(db()));
    EXPECT_EQ(r.code, 0) << r.output;
    return nlohmann::json::parse(r.output);
  }
  // A session's identification run (1) and closed-loop run (2) of `rig`
  // on the simulator, then a plant model of it trained from both, briefly.
  test::ProcessResult plant_of(const std::string& rig, const std::string& script, const std::string& plant) {
    session(rig, script);
    return console("train --rig " + rig + " --run 1 --run 2 --plant --out " + shell_quote(plant) +
                   " --seeds 1 --epochs 5 --lbfgs 20 --db " + shell_quote(db()));
  }
};

// Every float of two runs' samples, bit for bit, step by step.
void expect_same_samples(RunStore& store, int64_t a, int64_t b) {
  const RunSeries x = store.series(a), y = store.series(b);
  ASSERT_EQ(x.rows(), y.rows());
  ASSERT_GT(x.rows(), 500u);
  EXPECT_EQ(x.step, y.step);
  const auto same = [](const std::vector<float>& p, const std::vector<float>& q) {
    return p.size() == q.size() && std::memcmp(p.data(), q.data(), p.size() * sizeof(float)) == 0;
  };
  EXPECT_TRUE(same(x.y_ref, y.y_ref)) << "y_ref";
  EXPECT_TRUE(same(x.y_hat, y.y_hat)) << "y_hat";
  EXPECT_TRUE(same(x.y_true, y.y_true)) << "y_true";
  EXPECT_TRUE(same(x.u, y.u)) << "u";
  EXPECT_TRUE(same(x.cost, y.cost)) << "cost";
  EXPECT_EQ(x.iterations, y.iterations);
  ASSERT_TRUE(x.has_l);
  ASSERT_TRUE(y.has_l);
  EXPECT_TRUE(same(x.l, y.l)) << "l";
}

// A Swirl on hasel under tuned parameters, replayed with nothing changed:
// the same samples, every float of them, and the replay says so.
TEST_F(RunsReplay, NothingChangedGivesTheRecordingBackBitForBit) {
  session("hasel", "set Q 2e6 2e6 1e6\nset Lambda 2\nref swirl\nrun 8s label=swirl\n");
  const auto r = console("runs replay 1 --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "run 2: run 1 replayed on nlsoft-posix")) << r.output;
  EXPECT_TRUE(contains(r.output, "nothing changed")) << r.output;
  EXPECT_TRUE(contains(r.output, "y_true and u identical at all")) << r.output;
  EXPECT_TRUE(contains(r.output, "same parameters at start")) << r.output;
  RunStore store(db());
  expect_same_samples(store, 1, 2);
  const RunRow replayed = store.run(2);
  EXPECT_EQ(replayed.kind, "replay");
  EXPECT_EQ(replayed.label, "replay of run 1");
  EXPECT_EQ(replayed.model_hash, store.run(1).model_hash);
  const nlohmann::json c = compare(1, 2);
  EXPECT_EQ(c["a"]["nrmse"], c["b"]["nrmse"]);
  EXPECT_TRUE(c["param_diff"].empty()) << c.dump();
}

// A constructed case: Q a hundredth of the run's weighs tracking error
// less against input effort, so the replay tracks worse with less effort;
// a hundredfold Lambda spends less effort too. The change is in the
// replay's parameters and label, not in the recording's.
TEST_F(RunsReplay, AChangedWeightMovesTrackingAndEffortTheWayItWeighs) {
  session("hasel", "ref swirl\nrun 8s label=swirl\n");
  auto r = console("runs replay 1 --set Q=1e4 --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "changed: Q=1e4")) << r.output;
  EXPECT_TRUE(contains(r.output, "steps identical; apart from step")) << r.output;
  nlohmann::json c = compare(1, 2);
  EXPECT_GT(c["b"]["nrmse"].get<double>(), c["a"]["nrmse"].get<double>() * 1.05) << c.dump();
  EXPECT_LT(c["b"]["u_effort"].get<double>(), c["a"]["u_effort"].get<double>()) << c.dump();
  EXPECT_EQ(c["param_diff"]["Q"][1], "10000 10000 10000") << c.dump();

  r = console("runs replay 1 --set Lambda=100 --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  c = compare(1, 3);
  EXPECT_LT(c["b"]["u_effort"].get<double>(), c["a"]["u_effort"].get<double>()) << c.dump();
  RunStore store(db());
  EXPECT_EQ(store.run(3).label, "replay of run 1: Lambda=100");
}

// --controller pid: msd's steps through the rig file's PID baseline (the
// paper's), offline, is the very loop `simulate --controller pid` runs on
// that reference for as many steps: the same tracking figure. A replay of a
// rig without [pid], or with an MPC change beside it, is refused with
// nothing recorded.
TEST_F(RunsReplay, APidReplayIsTheLoopSimulateRunsWithThePid) {
  session("msd", "ref steps\nrun 4s label=steps\n");
  session("hasel", "ref swirl\nrun 1s label=swirl\n");
  auto r = console("runs replay 1 --controller pid --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "run 3: run 1's reference through rig msd's PID baseline (kp 1.93, ki 4.01, kd 5.99, "
                                 "output scale 60)"))
      << r.output;
  RunStore store(db());
  const RunRow pid = store.run(3);
  EXPECT_EQ(pid.kind, "replay");
  EXPECT_EQ(pid.label, "replay of run 1: controller pid");
  const RunSeries rec = store.series(1), rep = store.series(3);
  ASSERT_GT(rec.rows(), 3000u);
  EXPECT_EQ(rep.rows(), size_t(rec.step.back()) + 1) << "a step of the replay for every step of the run";
  EXPECT_FALSE(rep.has_y_hat) << "a PID predicts nothing";
  ASSERT_TRUE(rep.has_y_true && rep.has_u);

  const auto sim = console("simulate --rig msd --controller pid --reference steps --steps " +
                           std::to_string(rep.rows()) + " --json");
  ASSERT_EQ(sim.code, 0) << sim.output;
  // 4 s of the steps hold the first level: its RMSE, not the nRMSE of a flat reference.
  const double simulated = nlohmann::json::parse(sim.output)["rmse"][0].get<double>();
  const nlohmann::json c = compare(1, 3);
  EXPECT_NEAR(c["b"]["rmse"][0].get<double>(), simulated, 1e-6 * simulated) << c.dump();
  EXPECT_NE(c["a"]["rmse"][0], c["b"]["rmse"][0]) << "the MPC's run and the PID's are other loops";

  const std::vector<std::pair<std::string, std::string>> refused = {
      {"2 --controller pid", "rig 'hasel'"},
      {"1 --controller pid --set Lambda=1", "--set changes the MPC"},
      {"1 --controller pid --model " + shell_quote(dir_.file("m.nlsm")), "--model changes the MPC"},
      {"1 --controller lqr", "--controller"},
  };
  for (const auto& [args, message] : refused) {
    r = console("runs replay " + args + " --db " + shell_quote(db()));
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, message)) << args << "\n" << r.output;
  }
  EXPECT_TRUE(contains(console("runs replay 2 --controller pid --db " + shell_quote(db())).output, "has no [pid] table"));
  EXPECT_EQ(RunStore(db()).last_run_id(), 3) << "a refused replay recorded a run";
}

// What cannot be replayed as it ran is refused, naming the run and why,
// with nothing recorded; what a replay does not repeat is said.
TEST_F(RunsReplay, RunsThatCannotBeReplayedAreRefusedAndWhatIsNotRepeatedIsSaid) {
  session("hasel", "ident prbs 2s seed=3\nref swirl\nrun 3s label=swirl\nset Lambda 2\n");
  // Run 3: a board's run, as a console records one.
  ASSERT_EQ(test::record_a_boards_run(db()), 3);
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"1", "run 1 is an identification run"},
      {"3", "run 3 was recorded on nlsoft-f446 0.1.0 (hasel), not on the simulator"},
      {"9", "no run 9"},
      {"2 --rig tendon", "run 2 was recorded on rig 'hasel', not on rig 'tendon'"},
      {"2 --set Q", "--set Q: give NAME=VALUE"},
      {"2 --set Q=-1", "Q[0] = -1 is out of range"},
      {"2 --set nope=1", "unknown parameter 'nope'"},
      {"2 --model " + shell_quote(dir_.file("none.nlsm")), "cannot open model file"},
  };
  for (const Case& c : cases) {
    const auto r = console("runs replay " + c.args + " --db " + shell_quote(db()));
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, c.message)) << c.args << "\n" << r.output;
  }
  RunStore store(db());
  EXPECT_EQ(store.last_run_id(), 3) << "a refused replay recorded a run";
}

// A run during which a parameter changed: the replay keeps what it started
// with and says so before it runs.
TEST_F(RunsReplay, AParameterChangedDuringTheRunIsSaidNotRepeated) {
  session("hasel", "ref swirl\nrun 2s label=swirl\n");
  {
    // The console records a change during a run as a params row after its start.
    Recorder rec(db());
    rec.add_param_change(1, 1.5, "Lambda", "3 3 3 3 3 3");
    rec.flush();
  }
  const auto r = console("runs replay 1 --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "Lambda was changed 1 time during run 1; the replay keeps the value it started with"))
      << r.output;
}

// Run `id` as though a board had recorded it: its firmware's name is all
// that tells a console's recording of a board from one of the simulator.
void mark_as_a_boards(const std::string& db, int64_t id) {
  Db d(db, false);
  d.exec(("UPDATE runs SET firmware = 'nlsoft-f446 0.1.0' WHERE id = " + std::to_string(id)).c_str());
}

// A run of a board, which no simulator can replay, replays through a plant
// model trained from the rig's runs (an identification run and a closed-loop
// one, with the sensors it streams): the model's fit is said before, the
// replay is recorded as one and marked so, and a change moves it the way
// it weighs. Without --plant the refusal names the way.
TEST_F(RunsReplay, ABoardsRunReplaysThroughAPlantModelTrainedFromTheRigsRuns) {
  const std::string plant = dir_.file("hasel.nlsp");
  auto r = plant_of("hasel", "ident prbs 20s seed=3\nref swirl\nrun 6s label=swirl\n", plant);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "its 3 outputs and 18 sensors, 21 channels in 4 parts")) << r.output;
  EXPECT_TRUE(contains(r.output, "plant model free run of the last tenth of each run")) << r.output;
  mark_as_a_boards(db(), 2);

  r = console("runs replay 2 --db " + shell_quote(db()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "train --rig hasel --run ID... --plant --out hasel.nlsp")) << r.output;

  r = console("runs replay 2 --plant " + shell_quote(plant) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "the plant is the plant model")) << r.output;
  EXPECT_TRUE(contains(r.output, "free run of the last tenth of each run")) << r.output;
  EXPECT_TRUE(contains(r.output, "run 3: run 2 replayed on nlsoft-posix")) << r.output;
  RunStore store(db());
  const RunRow replayed = store.run(3);
  EXPECT_EQ(replayed.kind, "replay");
  EXPECT_TRUE(contains(replayed.notes, "plant model")) << replayed.notes;
  const RunSeries rec = store.series(2), rep = store.series(3);
  ASSERT_EQ(rep.rows(), rec.rows());
  ASSERT_TRUE(rep.has_y_true && rep.has_l);
  // The plant starts where the run started.
  for (int j = 0; j < 3; ++j) EXPECT_EQ(rep.y_true[size_t(j)], rec.y_true[size_t(j)]) << j;

  // Ten thousand times Lambda: the input changes cost that much more,
  // through the same plant model as through the rig.
  r = console("runs replay 2 --plant " + shell_quote(plant) + " --set Lambda=1e4 --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  // What the plant model gives with nothing changed, said beside it (run 3's
  // figure), and not recorded.
  EXPECT_TRUE(contains(r.output, fmt::format("through the plant model with nothing changed, run 2 tracks at nrmse {:.4g}",
                                             compare(2, 3)["b"]["nrmse"].get<double>())))
      << r.output;
  const nlohmann::json c = compare(3, 4);
  EXPECT_LT(c["b"]["u_effort"].get<double>(), 0.5 * c["a"]["u_effort"].get<double>()) << c.dump();

  // The tuner on the same replays: a board's run tuned without the board.
  r = console("tune --replay 2 --plant " + shell_quote(plant) + " --param 'Lambda=0.1..10:log' --budget 4 --save " +
              shell_quote(dir_.file("t.params")) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "tuning on replays of run 2")) << r.output;
  EXPECT_EQ(RunStore(db()).run(5).kind, "replay");
  // The same from a session's script, on the board's run: the firmware
  // connected is untouched until apply.
  const std::string script = dir_.file("t.nls");
  std::ofstream(script) << "tune replay=2 plant=" << plant << " Lambda=0.1..10:log budget=3 save=" << dir_.file("s.params")
                        << "\n";
  r = console("--sim hasel --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "tune: run 2 (780 steps at 130 Hz) replayed per candidate")) << r.output;
  std::ofstream(script) << "tune plant=" << plant << " Lambda=0.1..10:log budget=3\n";
  r = console("--sim hasel --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "plant=FILE names the plant model")) << r.output;
  r = console("tune --plant " + shell_quote(plant) + " --sim hasel --param 'Lambda=0.1..10:log'");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it goes with --replay N")) << r.output;
}

// What a plant model cannot stand in for is refused with nothing recorded:
// a file that is no plant model, a plant of another rig, a run whose first
// sample holds no measured output to start it from.
TEST_F(RunsReplay, APlantModelThatCannotStandInIsRefused) {
  const std::string plant = dir_.file("msd.nlsp");
  auto r = plant_of("msd", "ident prbs 3s seed=2\nref steps\nrun 3s label=steps\n", plant);
  ASSERT_EQ(r.code, 0) << r.output;
  session("hasel", "ref swirl\nrun 1s label=swirl\n");  // run 3
  {
    // Run 4: msd's, from a board whose telemetry carried no y_true.
    Recorder rec(db());
    RunInfo ri;
    ri.platform = "msd";
    ri.firmware = "nlsoft-f446 0.1.0";
    ri.n = 1, ri.m = 1;
    ri.loop_rate_hz = 1000;
    ri.reference = RunStore(db()).run(2).reference;
    ri.params = {{"Lambda", "1"}};
    ASSERT_EQ(rec.begin_run(ri), 4);
    Sample smp;
    smp.n = 1, smp.m = 1;
    smp.mask = protocol::telemetry_field::kStep | protocol::telemetry_field::kU;
    rec.add_sample(4, smp);
    rec.end_run(4, "completed", 1, 0);
  }
  std::ofstream(dir_.file("short.nlsp"), std::ios::binary) << "NLSP";
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"3 --plant " + shell_quote(plant), "is a plant model of rig 'msd' (m = 1, n = 1, w = 0), not of run 3's rig 'hasel'"},
      {"3 --plant " + shell_quote(dir_.file("short.nlsp")), "is not a valid plant model: no NLSP header"},
      {"3 --plant " + shell_quote(std::string(NLSOFT_SOURCE_MODELS_DIR) + "/hasel.nlsm"), "no NLSP header"},
      {"3 --plant " + shell_quote(dir_.file("none.nlsp")), "cannot open"},
      {"4 --plant " + shell_quote(plant), "run 4's first sample holds no measured output (y_true)"},
      {"2 --plant " + shell_quote(plant) + " --controller pid --set Lambda=1", "--set changes the MPC"},
  };
  for (const auto& [args, message] : refused) {
    r = console("runs replay " + args + " --db " + shell_quote(db()));
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, message)) << args << "\n" << r.output;
  }
  EXPECT_EQ(RunStore(db()).last_run_id(), 4) << "a refused replay recorded a run";
  // A plant model measures its fit on the last tenth of every run it trains on.
  r = console("train --rig msd --run 1 --validate-run 2 --plant --out " + shell_quote(dir_.file("v.nlsp")) + " --db " +
              shell_quote(db()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "--plant holds out the last tenth of every run")) << r.output;

  // The PID baseline through the plant model of msd's own runs.
  mark_as_a_boards(db(), 2);
  r = console("runs replay 2 --controller pid --plant " + shell_quote(plant) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "PID baseline (kp 1.93")) << r.output;
  EXPECT_TRUE(contains(r.output, "plant model " + plant)) << r.output;
  EXPECT_EQ(RunStore(db()).run(5).kind, "replay");
}

}  // namespace
}  // namespace nlsoft::console
