// The session around the runs: `runs list` with reference and nRMSE (and
// --json), `runs label`, `runs delete`, a reference sent mid-run recorded,
// and the CLI's contract (--version; usage errors exit 2).
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>
#include <nlohmann/json.hpp>

#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sqlite.hpp"
#include "app/support/run_process.hpp"
#include "app/support/process_tree.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;

using test::run_process;
using test::shell_quote;

class RunsCommands : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }
  test::ProcessResult console(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args);
  }
  test::ProcessResult runs(const std::string& args) const { return console("runs " + args + " --db " + shell_quote(db())); }
  // Run 1 starts with no reference and gets Infinity during it; run 2 is a
  // Swirl from the start.
  void record() {
    const std::string script = dir_.file("s.nls");
    std::ofstream(script) << "start\nwait 500ms\nref infinity\nwait 500ms\nstop\nref swirl\nrun 1s label=swirl\n";
    const auto r = console("--sim hasel --db " + shell_quote(db()) + " --script " + shell_quote(script));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  std::string db() const { return dir_.file("runs.db"); }
  test::TempDir dir_;
};

TEST_F(RunsCommands, ListShowsReferenceAndNrmseAndAMidRunReferenceIsRecorded) {
  record();
  auto r = runs("list");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "reference")) << r.output;
  EXPECT_TRUE(contains(r.output, "nrmse")) << r.output;
  EXPECT_TRUE(contains(r.output, "swirl")) << r.output;

  r = runs("list --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 2u);
  // Run 1 started on the firmware's own reference (the rig's paper task),
  // named as such, not an empty one.
  EXPECT_EQ(j[0]["reference"]["kind"], "swirl") << j.dump();
  EXPECT_TRUE(contains(j[0]["reference"].value("source", ""), "start-up reference")) << j.dump();
  EXPECT_EQ(j[1]["reference"]["kind"], "swirl");
  EXPECT_EQ(j[1]["label"], "swirl");
  EXPECT_TRUE(j[0]["nrmse"].is_number()) << j.dump();

  // Infinity, sent during run 1: the change, with its time, in the run's log.
  r = runs("show 1");
  EXPECT_TRUE(contains(r.output, "reference = {")) << r.output;
  EXPECT_TRUE(contains(r.output, "\"kind\":\"infinity\"")) << r.output;
}

// A run whose samples carry no measured output (a rig nothing measures;
// here run 2's y_true taken out of the database): every figure of tracking
// says it was scored on the model's prediction, and run 1's, measured, not.
TEST_F(RunsCommands, ARunWithoutAMeasuredOutputSaysItsTrackingIsTheModelsPrediction) {
  record();
  {
    Db file(db(), Db::Access::ReadWrite);
    file.exec("UPDATE samples SET y_true=NULL WHERE run_id=1");
  }
  const std::string words = "no measured output: tracking scored on the model's prediction";
  auto r = runs("show 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "  " + words)) << r.output;
  r = runs("show 2");
  EXPECT_FALSE(contains(r.output, words)) << r.output;
  r = runs("show 1 --json");
  EXPECT_EQ(nlohmann::json::parse(r.output)["measured_output"], false) << r.output;

  r = runs("list");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "*: " + words)) << r.output;
  std::istringstream lines(r.output);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("    1 ", 0) == 0) {
      EXPECT_TRUE(contains(line, "* ")) << line;  // its nrmse marked
    }
    if (line.rfind("    2 ", 0) == 0) {
      EXPECT_FALSE(contains(line, "*")) << line;
    }
  }
  r = runs("list --json");
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j[0]["measured_output"], false);
  EXPECT_EQ(j[1]["measured_output"], true);
}

TEST_F(RunsCommands, LabelAndDeleteChangeOneRunWhole) {
  record();
  auto r = runs("label 2 " + shell_quote("Lambda 4, smoother"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(RunStore(db()).run(2).label, "Lambda 4, smoother");
  r = runs("delete 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "run 1 deleted")) << r.output;
  {
    RunStore store(db());
    const auto list = store.list();
    ASSERT_EQ(list.size(), 1u);
    EXPECT_EQ(list[0].id, 2);
    EXPECT_TRUE(store.params(1).empty());
    EXPECT_GT(store.series(2).rows(), 0u) << "the other run keeps its samples";
    Db raw(db(), Db::Access::ReadOnly);
    Stmt c = raw.prepare("SELECT count(*) FROM samples WHERE id < ?");
    c.bind(1, sample_key(2, 0));
    ASSERT_TRUE(c.step());
    EXPECT_EQ(c.int64(0), 0) << "the run's samples go with it";
  }
  r = runs("delete 9");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "no run 9")) << r.output;
  r = runs("label 9 x");
  EXPECT_EQ(r.code, 2) << r.output;
}

// Without --csv (or with -) the CSV goes to standard output, the report to
// standard error, so `runs export 1 > run.csv` and pipes work.
TEST_F(RunsCommands, ExportWritesToStandardOutputByDefault) {
  record();
  const auto r = run_process("sh -c " + shell_quote(std::string(NLSOFT_CONSOLE_BIN) + " runs export 2 --db " +
                                                    shell_quote(db()) + " 2>/dev/null"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.rfind("k,", 0), 0u) << r.output.substr(0, 200);
  size_t rows = 0;
  for (char c : r.output) rows += c == '\n';
  EXPECT_EQ(rows, RunStore(db()).run(2).samples + 1) << "a header and one line per sample, nothing else";
}

TEST_F(RunsCommands, AnUnfinishedRunIsDeletedOnlyWithForce) {
  int64_t id = 0;
  {
    Recorder rec(db());
    RunInfo ri;
    ri.platform = "hasel";
    ri.n = 3;
    ri.m = 6;
    id = rec.begin_run(ri);
    rec.flush();
  }
  auto r = runs("delete " + std::to_string(id));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "unfinished")) << r.output;
  EXPECT_EQ(RunStore(db()).list().size(), 1u) << "nothing deleted";
  r = runs("delete --force " + std::to_string(id));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(RunStore(db()).list().empty());
}

// `runs delete 2 --force` while another console records run 2: refused,
// naming that console, and nothing deleted (run 1 asked for with it stays
// too). Once that console is killed (-9: it ends nothing), its mark is
// stale: the refusal says so without --force, and --force deletes the run
// saying whose it was.
TEST_F(RunsCommands, ARunBeingRecordedIsNotDeletedUntilItsRecorderIsGone) {
  const std::string script = dir_.file("long.nls");
  std::ofstream(script) << "run 1s label=short\nrun 600s label=long\n";
  const std::string command = "exec " + std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + shell_quote(db()) +
                              " --script " + shell_quote(script) + " >/dev/null 2>&1";
  const pid_t pid = test::start_shell(command);
  ASSERT_GT(pid, 0);
  // Until run 2 has samples; the limit only keeps a broken console from
  // hanging the suite.
  bool recording = false;
  for (int i = 0; i < 600 && !recording; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    try {
      const auto list = RunStore(db()).list();
      recording = list.size() == 2 && list[1].samples > 0;
    } catch (const std::exception&) {
    }
  }
  if (!recording) ::kill(pid, SIGKILL);
  ASSERT_TRUE(recording) << "run 2 never started";
  auto r = runs("delete 1 2 --force");
  const std::string pid_text = std::to_string(pid);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "run 2 is being recorded by nlsoft-console (PID " + pid_text + "); stop that run first"))
      << r.output;
  EXPECT_EQ(RunStore(db()).list().size(), 2u) << "something was deleted";
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  r = runs("delete 2");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "PID " + pid_text + " is no longer running")) << r.output;
  EXPECT_EQ(RunStore(db()).list().size(), 2u) << "deleted without --force";
  r = runs("delete 2 --force");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "run 2: its recorder, nlsoft-console (PID " + pid_text + "), left it unfinished"))
      << r.output;
  const auto left = RunStore(db()).list();
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(left[0].label, "short");
}

// A firmware that died 3 s into a 30 s run at 130 Hz: the telemetry was
// silent for 3 s before the run gave up, 351 frames lost in it (a slower
// loop than set). Each time is named for what it is, and the frames' time
// is what they are at the run's rate.
TEST_F(RunsCommands, AGapSaysItsFramesTimeAtTheRunsRateAndTheSilenceApart) {
  int64_t id = 0;
  {
    Recorder rec(db());
    RunInfo ri;
    ri.platform = "hasel";
    ri.n = 3;
    ri.m = 6;
    ri.loop_rate_hz = 130;
    id = rec.begin_run(ri);
    rec.add_gap(id, 383, 351, "run ended early: telemetry stopped arriving", 3.0);
    rec.end_run(id, "ended early: telemetry stopped arriving (none for 3.0 s: firmware stopped or link lost)", 384, 351);
  }
  const auto r = runs("show " + std::to_string(id));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "gap after sample 383: 351 frames lost (2.7 s at 130 Hz); telemetry silent for 3.00 s"))
      << r.output;
  EXPECT_FALSE(contains(r.output, "lost over")) << r.output;
}

// Runs recorded straight into the database: label, how they ended.
int64_t recorded_run(const std::string& db, const std::string& label, const std::string& reason) {
  Recorder rec(db);
  RunInfo ri;
  ri.label = label;
  ri.platform = "hasel";
  ri.n = 3;
  ri.m = 6;
  ri.loop_rate_hz = 130;
  const int64_t id = rec.begin_run(ri);
  if (!reason.empty()) rec.end_run(id, reason, 0, 0);
  rec.flush();
  return id;
}

// The ids a `runs list` prints, in order.
std::vector<int64_t> listed_ids(const std::string& out) {
  std::vector<int64_t> ids;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    int64_t id = 0;
    std::string started;
    if (words >> id >> started && started.size() >= 10 && started[4] == '-') ids.push_back(id);
  }
  return ids;
}

// The ended column holds a word or two; the sentence is in `runs show`.
TEST_F(RunsCommands, ListSaysHowARunEndedInAWordAndShowSaysItInFull) {
  const std::string watchdog =
      "ended early: the firmware's link watchdog tripped (nothing from the console for watchdog_ms); it is holding";
  recorded_run(db(), "calm", "completed");
  const int64_t tripped = recorded_run(db(), "tripped", watchdog);
  recorded_run(db(), "left", "stopped by the user");
  recorded_run(db(), "crashed", "");
  const auto r = runs("list");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* word : {"finished", "early: watchdog", "stopped", "unfinished"})
    EXPECT_TRUE(contains(r.output, word)) << word << "\n" << r.output;
  EXPECT_FALSE(contains(r.output, "nothing from the console")) << r.output;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    if (!listed_ids(line).empty()) {
      EXPECT_LE(line.size(), 120u) << line;
    }
  }
  EXPECT_TRUE(contains(r.output, "nrmse(run)")) << r.output;
  EXPECT_TRUE(contains(r.output, "nrmse(run): over the whole recorded run")) << r.output;
  const auto show = runs("show " + std::to_string(tripped));
  EXPECT_TRUE(contains(show.output, watchdog)) << show.output;
}

TEST_F(RunsCommands, ListKeepsTheLastRunsALabelAndASinceTime) {
  for (const char* label : {"baseline", "Lambda 4", "BASELINE again", "sweep", "baseline 3"})
    recorded_run(db(), label, "completed");
  auto r = runs("list --last 2");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(listed_ids(r.output), (std::vector<int64_t>{4, 5})) << r.output;
  r = runs("list --label baseline");
  EXPECT_EQ(listed_ids(r.output), (std::vector<int64_t>{1, 3, 5})) << "a substring, any case\n" << r.output;
  r = runs("list --label baseline --last 1");
  EXPECT_EQ(listed_ids(r.output), (std::vector<int64_t>{5})) << r.output;
  r = runs("list --since 2h");
  EXPECT_EQ(listed_ids(r.output).size(), 5u) << r.output;
  r = runs("list --since 2000-01-01");
  EXPECT_EQ(listed_ids(r.output).size(), 5u) << r.output;
  r = runs("list --since 2999-01-01T10:30");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(listed_ids(r.output).empty()) << r.output;
  EXPECT_TRUE(contains(r.output, "none of the 5 runs")) << r.output;
  r = runs("list --json --last 1");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["id"], 5);
  for (const char* bad : {"soon", "2026-13-01", "-2h", "2h ago"}) {
    r = runs(std::string("list --since ") + shell_quote(bad));
    EXPECT_EQ(r.code, 2) << bad << ": " << r.output;
    EXPECT_TRUE(contains(r.output, "give a date")) << r.output;
  }
}

// `run 1s` is 130 control steps of the firmware's time; under --sim-fast the
// simulator runs far ahead of the wall clock and past the end, and the
// run's summary says all of it.
TEST_F(RunsCommands, ARunsSummarySaysItsSecondsAreTheFirmwaresNotTheWallClocks) {
  const std::string script = dir_.file("fast.nls");
  std::ofstream(script) << "run 1s\n";
  const auto r = console("--sim hasel --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "1 s asked = 130 control steps at 130 Hz (the firmware's time, not wall time): "))
      << r.output;
  const uint64_t samples = RunStore(db()).run(1).samples;
  EXPECT_TRUE(contains(r.output, std::to_string(samples) + " samples = ")) << r.output;
  if (samples > 143) {
    EXPECT_TRUE(contains(r.output, "runs past the end until RUN_STOP reaches it")) << r.output;
  }
}

// `runs delete 3 1`: several runs, reported in the order given; with one
// id unknown, none is deleted.
TEST_F(RunsCommands, DeleteTakesSeveralIdsInTheOrderGivenAllOrNothing) {
  {
    Recorder rec(db());
    for (int i = 0; i < 3; ++i) {
      RunInfo ri;
      ri.platform = "msd";
      ri.n = 1;
      ri.m = 1;
      const int64_t id = rec.begin_run(ri);
      rec.end_run(id, "completed", 0, 0);
    }
  }
  auto r = runs("delete 2 9");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "no run 9")) << r.output;
  EXPECT_EQ(RunStore(db()).list().size(), 3u) << "nothing deleted";
  r = runs("delete 3 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output, "run 3 deleted\nrun 1 deleted\n");
  const auto left = RunStore(db()).list();
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(left[0].id, 2);
}

// The examples `runs --help` gives, as printed, against two recorded runs
// (its ids 12 and 13 mapped to 1 and 2), in order: the last deletes one.
TEST_F(RunsCommands, EveryRunsExampleInTheHelpRuns) {
  record();
  const auto help = console("runs --help");
  ASSERT_EQ(help.code, 0) << help.output;
  // The capture `runs merge-y 12 mocap.csv` names: 2 s of hasel's three
  // outputs at 100 Hz, on a clock of its own.
  {
    std::ofstream f(dir_.file("mocap.csv"));
    f << "time,y0,y1,y2\n";
    for (int k = 0; k < 200; ++k)
      f << 40.0 + k * 0.01 << "," << std::sin(k * 0.05) << "," << std::cos(k * 0.07) << "," << 4 + std::sin(k * 0.03) << "\n";
  }
  std::istringstream lines(help.output);
  int ran = 0;
  for (std::string line; std::getline(lines, line);) {
    const std::string prefix = "  nlsoft-console runs ";
    if (line.rfind(prefix, 0) != 0) continue;
    std::string args = line.substr(prefix.size());
    for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{{" 12 13", " 1 2"}, {" 12", " 1"}}) {
      const size_t at = args.find(from);
      if (at != std::string::npos) args.replace(at, from.size(), to);
    }
    const bool draws = args.find("--svg") != std::string::npos || args.find("--png") != std::string::npos;
    if (draws && run_process("command -v gnuplot").code != 0) continue;
    const auto r = run_process("cd " + shell_quote(dir_.path) + " && " + std::string(NLSOFT_CONSOLE_BIN) + " runs " +
                               args + " --db " + shell_quote(db()));
    EXPECT_EQ(r.code, 0) << line << "\n" << r.output;
    ++ran;
  }
  EXPECT_GE(ran, 6) << help.output;
}

// The example script of `nlsoft-console --help`, as printed, passes against
// the simulated HASEL rig: its expects hold.
TEST(ConsoleExamples, TheHelpExampleScriptPassesOnTheSimulatedRig) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  const auto help = run_process(std::string(NLSOFT_CONSOLE_BIN) + " --help");
  ASSERT_EQ(help.code, 0) << help.output;
  const size_t at = help.output.find("Example script");
  ASSERT_NE(at, std::string::npos) << help.output;
  std::istringstream lines(help.output.substr(help.output.find('\n', at) + 1));
  std::string script;
  for (std::string line; std::getline(lines, line) && line.rfind("  ", 0) == 0;) script += line.substr(2) + "\n";
  // The shipped hasel model's 10 s from rest measured nrmse 0.045 to 0.052
  // over 12 runs (when the run starts against the simulator's steps moves
  // it): the example's bound is above what it does, not on it.
  ASSERT_NE(script.find("expect nrmse < 0.06"), std::string::npos) << script;
  test::TempDir dir;
  const std::string file = dir.file("example.nls");
  std::ofstream(file) << script;
  // --sim-fast: what the script asks of the controller, not 25 s of the wall clock.
  const auto r =
      run_process(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --sim-fast --no-record --script " + shell_quote(file));
  EXPECT_EQ(r.code, 0) << script << r.output;
  EXPECT_NE(r.output.find("ok: nrmse = "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("2 expects held, 0 failed"), std::string::npos) << r.output;
}

TEST(ConsoleCli, VersionAndUsageErrorsExitTwo) {
  auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " --version");
  EXPECT_EQ(r.code, 0) << r.output;
  // The protocol as its specification names it, on its title line.
  std::ifstream spec(std::string(NLSOFT_SOURCE_MODELS_DIR) + "/../../protocol/PROTOCOL.md");
  std::string title;
  std::getline(spec, title);
  const std::string version = title.substr(title.rfind(' ') + 1);
  EXPECT_EQ(title, "# nlsoft wire protocol, version " + version);
  EXPECT_TRUE(contains(r.output, "nlsoft-console 0.1.0, wire protocol " + version + " ")) << r.output << title;
  for (const char* args : {"--no-such-option", "runs show", "runs show notanumber", "--sim nowhere",
                           "runs plot 1 2 3 --svg x.svg"}) {
    r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.output;
  }
}

// The live console's footer (its examples, the script commands) belongs to
// `nlsoft-console --help` only; a command's help ends with its own words.
TEST(ConsoleCli, ACommandsHelpDoesNotRepeatTheConsolesFooter) {
  const auto main_help = run_process(std::string(NLSOFT_CONSOLE_BIN) + " --help");
  ASSERT_TRUE(contains(main_help.output, "Script commands")) << main_help.output;
  for (const char* command : {"model", "model info", "simulate", "dataset", "train", "tune", "runs", "runs list",
                              "conformance", "flash"}) {
    const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + command + " --help");
    EXPECT_EQ(r.code, 0) << command << ": " << r.output;
    EXPECT_FALSE(contains(r.output, "Script commands")) << command << ":\n" << r.output;
    EXPECT_FALSE(contains(r.output, "Example script")) << command << ":\n" << r.output;
  }
}

}  // namespace
}  // namespace nlsoft::console
