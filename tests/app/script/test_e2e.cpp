// End to end over a pty: nlsoft-console --sim runs nlsoft-firmware-sim and
// executes scripts headless; the recording is then checked in the database.
#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "app/link/sim_launcher.hpp"
#include "app/live/reference_table.hpp"
#include "app/record/run_metrics.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sqlite.hpp"
#include "app/support/process_tree.hpp"
#include "app/support/run_process.hpp"
#include "shared/plant_hasel.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

using test::run_process;
using test::shell_quote;

class ConsoleE2E : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }

  test::ProcessResult run_script(const std::string& text, const std::string& platform = "hasel",
                                 const std::string& extra = "") {
    script_ = dir_.file("tune.nls");
    std::ofstream(script_) << text;
    return run_process(fmt_command(platform, extra));
  }
  std::string fmt_command(const std::string& platform, const std::string& extra) const {
    return std::string(NLSOFT_CONSOLE_BIN) + " --sim " + platform + " --db " + shell_quote(db()) + " --script " +
           shell_quote(script_) + " " + extra;
  }
  std::string db() const { return dir_.file("runs.db"); }

  // Until a console started in the background has samples of run 1 in the
  // database (the recorder commits every 50 ms); the limit only keeps a
  // broken console from hanging the suite.
  bool wait_until_recording() const {
    for (int i = 0; i < 600; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      try {
        const auto runs = RunStore(db()).list();
        if (!runs.empty() && runs[0].samples > 0) return true;
      } catch (const std::exception&) {
      }
    }
    return false;
  }

  // A console started in the background, ended: its wait status (-1 if
  // waitpid failed) and what it wrote to `out`.
  static std::pair<int, std::string> wait_for_console(pid_t pid, const std::string& out) {
    int status = 0;
    if (::waitpid(pid, &status, 0) != pid) status = -1;
    std::ifstream in(out);
    return {status, std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>())};
  }

  // The simulator under a console started in the background, once the
  // console records; 0 (the console killed) if either never comes.
  pid_t simulator_once_recording(pid_t console) const {
    const bool recording = wait_until_recording();
    const pid_t sim = test::descendant_named(console, "nlsoft-firmware-sim");
    if (recording && sim > 0) return sim;
    ::kill(console, SIGKILL);
    return 0;
  }

  test::TempDir dir_;
  std::string script_;
};

TEST_F(ConsoleE2E, SetParametersUploadSwirlRunAndCheckTheRecording) {
  const std::string csv = dir_.file("swirl.csv");
  write_reference_csv(swirl_table(HaselPlant::kSwirlCentre, HaselPlant::kSwirlScale, 3), csv);
  const auto r = run_script(
      "# the tuning session of the issue, headless\n"
      "set Q 1e6 2e6 1e6\n"
      "set Lambda 1 1 1 1 1 1\n"
      "get Q\n"
      "ref load " + csv + " hold=1\n"
      "run 3s label=swirl-e2e\n"
      "note swirl from a CSV table, paper tuning\n"
      "expect lost == 0\n"
      "expect samples == 390\n"
      "export csv " + dir_.file("run.csv") + "\n");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("Q = 1e+06 2e+06 1e+06"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("uploaded and selected"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("ok: lost = 0 == 0"), std::string::npos) << r.output;

  RunStore store(db());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  const RunRow& run = runs[0];
  EXPECT_EQ(run.label, "swirl-e2e");
  EXPECT_EQ(run.notes, "swirl from a CSV table, paper tuning");
  EXPECT_EQ(run.platform, "hasel");
  EXPECT_EQ(run.end_reason, "completed");
  EXPECT_EQ(run.lost_frames, 0u);
  EXPECT_NE(run.reference.find("\"kind\":\"table\""), std::string::npos) << run.reference;
  const RunSeries s = store.series(run.id);
  EXPECT_EQ(s.rows(), 390u);  // 3 s at 130 Hz, every step and no more
  EXPECT_EQ(s.rows(), run.samples);
  EXPECT_TRUE(s.has_y_true);
  // Steps are consecutive (decimation 1) and the reference is the table's
  // first points: the Swirl rests at its centre for 30 points.
  for (size_t i = 1; i < s.rows(); ++i) ASSERT_EQ(s.step[i], s.step[i - 1] + 1) << "at sample " << i;
  EXPECT_EQ(s.step[0], 0u);
  EXPECT_FLOAT_EQ(s.y_ref[0], HaselPlant::kSwirlCentre[0]);
  bool q_at_start = false;
  for (const auto& p : store.params(run.id)) q_at_start |= p.at_start && p.name == "Q" && p.value == "1e+06 2e+06 1e+06";
  EXPECT_TRUE(q_at_start);
  std::ifstream exported(dir_.file("run.csv"));
  size_t lines = 0;
  for (std::string l; std::getline(exported, l);) ++lines;
  EXPECT_EQ(lines, s.rows() + 1);
}

// A timed run is its planned steps, however far past them the firmware
// gets before RUN_STOP reaches it: a fast simulator steps thousands of
// times in the console's 10 ms polls, so the same run recorded twice gave
// two lengths. Now every step of 2 s at 130 Hz, none after, and the same
// samples both times.
TEST_F(ConsoleE2E, AFastTimedRunRecordsItsPlannedStepsAndTheSameSamplesAgain) {
  RunSeries first;
  for (int round = 0; round < 2; ++round) {
    const auto r = run_script("run 2s label=fast\n", "hasel", "--sim-fast");
    ASSERT_EQ(r.code, 0) << r.output;
    RunStore store(db());
    ASSERT_EQ(store.list().size(), size_t(round + 1));
    const RunRow run = store.run(round + 1);
    EXPECT_EQ(run.end_reason, "completed");
    const RunSeries s = store.series(run.id);
    ASSERT_EQ(s.rows(), 260u);
    EXPECT_EQ(run.samples, 260u);
    for (size_t i = 1; i < s.rows(); ++i) ASSERT_EQ(s.step[i], s.step[0] + i) << "at sample " << i;
    if (round == 0) {
      first = s;
      continue;
    }
    EXPECT_EQ(s.y_true, first.y_true);
    EXPECT_EQ(s.u, first.u);
    EXPECT_EQ(s.y_ref, first.y_ref);
  }
}

TEST_F(ConsoleE2E, FailedExpectExitsOneWithFileAndLine) {
  const auto r = run_script("ref hold\nrun 500ms\nexpect samples > 1e9\nexpect lost == 0\n", "msd");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("tune.nls:3: expect samples > 1e+09 failed: samples = "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("ok: lost = 0 == 0"), std::string::npos) << r.output;
}

TEST_F(ConsoleE2E, RefusedParameterExitsTwoAndChangesNothing) {
  const auto r = run_script("get Q\nset Q[1] -5\n", "hasel");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("tune.nls:2: Q[1] = -5 is out of range [0, 1e+12]"), std::string::npos) << r.output;
  const auto after = run_script("get Q\n", "hasel");
  EXPECT_EQ(after.code, 0) << after.output;
  EXPECT_NE(after.output.find("Q = 1e+06 2e+06 1e+06"), std::string::npos) << after.output;
}

TEST_F(ConsoleE2E, ScriptErrorIsReportedBeforeConnecting) {
  const auto r = run_script("set Q 1 2 3\nrun ten seconds\n");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("tune.nls:2: 'ten' is not a duration"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("connected:"), std::string::npos) << r.output;
}

// A script is checked whole against the firmware's parameter list before
// its first command: the run on line 1 does not happen because of line 2,
// and every bad line is named, not only the first.
TEST_F(ConsoleE2E, AScriptIsCheckedWholeAgainstTheFirmwareBeforeAnythingRuns) {
  const auto r = run_script(
      "run 1s label=never\n"
      "set Lambda abc\n"
      "set Q 1 2\n"
      "get Nope\n"
      "set Q[7] 1\n"
      "sweep Q0 1 -3 run 1s\n"
      "ref swirl wobble=2\n"
      "set Q 1e6 2e6 1e6\n",
      "hasel");
  EXPECT_EQ(r.code, 2) << r.output;
  for (const char* line : {"tune.nls:2: ", "tune.nls:3: Q takes 3 values", "tune.nls:4: unknown parameter 'Nope'",
                           "tune.nls:5: Q[7]: Q has 3 elements", "tune.nls:6: Q[0] = -3 is out of range [0, 1e+12]",
                           "tune.nls:7: ", "6 errors in the script; nothing was run"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
  EXPECT_EQ(r.output.find("tune.nls:1:"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("tune.nls:8:"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("run 1 (never)"), std::string::npos) << "line 1 ran:\n" << r.output;
  RunStore store(db());
  EXPECT_TRUE(store.list().empty()) << "a run was recorded";
}

TEST_F(ConsoleE2E, EverySyntaxErrorIsReportedBeforeConnecting) {
  const auto r = run_script("run ten seconds\nfly 3\nwait -1s\n");
  EXPECT_EQ(r.code, 2) << r.output;
  for (const char* line : {"tune.nls:1: 'ten' is not a duration", "tune.nls:2: unknown command 'fly'",
                           "tune.nls:3: '-1s': a duration must be > 0", "3 errors in the script; nothing was run"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
  EXPECT_EQ(r.output.find("connected:"), std::string::npos) << r.output;
}

// A directory or a device opens and reads as nothing: not an empty script
// that succeeds.
TEST_F(ConsoleE2E, ADirectoryADeviceOrAMissingFileIsNoScript) {
  const std::string console = std::string(NLSOFT_CONSOLE_BIN) + " --sim msd --db " + shell_quote(db()) + " --script ";
  const auto d = run_process(console + shell_quote(dir_.path));
  EXPECT_EQ(d.code, 2) << d.output;
  EXPECT_NE(d.output.find(dir_.path + ":0: cannot read script: it is a directory"), std::string::npos) << d.output;
  const auto n = run_process(console + "/dev/null");
  EXPECT_EQ(n.code, 2) << n.output;
  EXPECT_NE(n.output.find("/dev/null:0: cannot read script: it is a character device, not a script"), std::string::npos) << n.output;
  const auto m = run_process(console + shell_quote(dir_.file("absent.nls")));
  EXPECT_EQ(m.code, 2) << m.output;
  EXPECT_NE(m.output.find("absent.nls:0: cannot read script: No such file or directory"), std::string::npos)
      << m.output;
  for (const auto* r : {&d, &n, &m}) EXPECT_EQ(r->output.find("connected:"), std::string::npos) << r->output;
}

// `devices` asks the firmware how each sensor chip answers; a rig and a
// firmware without chips say so rather than print nothing. Extra words are
// a syntax error, found before connecting.
TEST_F(ConsoleE2E, DevicesSaysHowEachChipAnswersOrThatThereAreNone) {
  auto r = run_script("devices\n", "msd");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("no sensor chips, in the file or the firmware"), std::string::npos) << r.output;
  r = run_script("devices all\n", "msd");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(":1:"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("connected"), std::string::npos) << r.output;
}

TEST_F(ConsoleE2E, ParamsSaveLoadShowsTheDiff) {
  const std::string saved = dir_.file("p.params");
  const auto r = run_script("params save " + saved + "\nset Q 5 5 5\nparams load " + saved + "\nget Q\n");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("Q: 5 5 5 -> 1e+06 2e+06 1e+06"), std::string::npos) << r.output;
}

TEST_F(ConsoleE2E, SweepPrintsATablePerSetting) {
  const auto r = run_script("ref hold\nsweep Q0 1 1000 run 300ms\n", "msd");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("Q0  run"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Q restored to 1"), std::string::npos) << r.output;
}

// Rows are comparable: each starts the reference over with the actuators
// neutral and is measured after a stated settling time, which the table says.
TEST_F(ConsoleE2E, SweepRowsSettleBeforeTheyAreMeasured) {
  const auto r = run_script("ref steps\nsweep Q0 1 1000 run 300ms settle=200ms\n", "msd");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("each row: the reference restarted from its first point, actuators from neutral; measured "
                          "over 0.3 s after 0.2 s to settle"),
            std::string::npos)
      << r.output;
  RunStore store(db());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 2u);
  for (const RunRow& run : runs) {
    EXPECT_GE(run.samples, 500u) << "settle + measured time recorded";
    // The table's samples column counts only the measured part (~300 at 1 kHz).
    long measured = -1;
    std::istringstream lines(r.output);
    for (std::string line; std::getline(lines, line);) {
      std::istringstream words(line);
      std::string value, id, samples;
      if (words >> value >> id >> samples && id == std::to_string(run.id)) measured = std::atol(samples.c_str());
    }
    EXPECT_GT(measured, 250) << r.output;
    EXPECT_LT(measured, 400) << r.output;
  }
  EXPECT_NE(run_script("sweep Q0 1 2 run 1s settle=soon\n", "msd").output.find("'soon' is not a duration"),
            std::string::npos);
}

// Disk full, as a file-size limit makes it: the shell's `ulimit -f` only,
// as a user would set it (the console itself must keep SIGXFSZ from killing
// it, so the write fails with EFBIG): the recording fails a second or so
// into a ten-minute run, and the console stops the run at once and says so,
// exit 2, instead of dying without a word (exit 153) or running on
// unrecorded. `timeout` turns waiting out the run into a failure here.
// The run is closed all the same: the database file stops growing first
// (the checkpoint finds it), while the log still has room for the close,
// on a loaded machine too (checkpoints follow the log's size, not only the
// clock). Every sample that arrived and is not in the file counts lost, in
// the database and in what the console says.
TEST_F(ConsoleE2E, ADiskFullStopsTheRunAtOnceAndCountsEveryUnsavedSampleLost) {
  script_ = dir_.file("full.nls");
  std::ofstream(script_) << "run 600s label=full\n";
  const auto r = run_process("ulimit -f 1200; exec timeout 80 " + fmt_command("msd", "--sim-rate 5000"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("stopped at once: recording failed"), std::string::npos) << r.output;
  RunStore store(db());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  const RunRow& run = runs[0];
  EXPECT_EQ(run.end_reason.rfind("recording failed: ", 0), 0u) << run.end_reason;
  const uint64_t saved = store.series(run.id).rows();
  EXPECT_EQ(run.samples, saved);
  EXPECT_GT(run.lost_frames, 0u) << "a failed write loses its batch at least";
  const std::string counts = fmt::format("{} of {} samples saved", saved, saved + run.lost_frames);
  EXPECT_NE(r.output.find(counts), std::string::npos) << counts << "\n" << r.output;
  EXPECT_NE(r.output.find(fmt::format("{} lost: not written: ", run.lost_frames)), std::string::npos) << r.output;
  const auto show = run_process(std::string(NLSOFT_CONSOLE_BIN) + " runs show 1 --db " + shell_quote(db()));
  EXPECT_NE(show.output.find(fmt::format("{} lost frame", run.lost_frames)), std::string::npos) << show.output;
}

// A colleague's sqlite3 shell holds the database in BEGIN EXCLUSIVE for 4 s
// of an 8 s run, longer than --db-busy 1: the samples that could not be
// saved are counted lost, the run has the gap and why, it ends "completed"
// once the lock goes, and the console says how many samples it saved.
TEST_F(ConsoleE2E, ADatabaseLockedPastTheBusyWindowIsAGapWithItsReason) {
  script_ = dir_.file("locked.nls");
  std::ofstream(script_) << "run 8s label=locked\n";
  const std::string out = dir_.file("console.out");
  const std::string command = "exec " + fmt_command("hasel", "--db-busy 1") + " >" + shell_quote(out) + " 2>&1";
  const pid_t pid = test::start_shell(command);
  ASSERT_GT(pid, 0);
  const bool recording = wait_until_recording();
  if (!recording) ::kill(pid, SIGKILL);
  ASSERT_TRUE(recording) << "the run never started";
  {
    Db shell(db(), false);
    shell.exec("BEGIN EXCLUSIVE");
    std::this_thread::sleep_for(std::chrono::seconds(4));
    shell.exec("ROLLBACK");
  }
  const auto [status, text] = wait_for_console(pid, out);
  ASSERT_NE(status, -1) << "waitpid failed";
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 0) << text;
  EXPECT_NE(text.find("has been locked by another process for over 1 s (--db-busy)"), std::string::npos) << text;
  RunStore store(db());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].end_reason, "completed");
  const auto gaps = store.gaps(runs[0].id);
  uint64_t locked_lost = 0;
  for (const GapRecord& g : gaps)
    if (g.reason.rfind("database locked by another process for ", 0) == 0) {
      locked_lost += g.lost_frames;
      EXPECT_GT(g.duration_s, 0.5) << g.reason;
    }
  ASSERT_GT(locked_lost, 0u) << "no gap for the lock";
  EXPECT_GE(runs[0].lost_frames, locked_lost);
  EXPECT_EQ(store.series(runs[0].id).rows(), runs[0].samples);
  const std::string saved = fmt::format("run 1: {} of {} samples saved; {} lost: database locked by another process for ",
                                        runs[0].samples, runs[0].samples + locked_lost, locked_lost);
  EXPECT_NE(text.find(saved), std::string::npos) << saved << "\n" << text;
  const auto show = run_process(std::string(NLSOFT_CONSOLE_BIN) + " runs show 1 --db " + shell_quote(db()));
  EXPECT_NE(show.output.find(fmt::format("{} frames lost", locked_lost)), std::string::npos) << show.output;
  EXPECT_NE(show.output.find("the samples lost span"), std::string::npos) << show.output;
}

// The simulator a headless console started, killed with -9 mid-run: the
// run ends early with how it ended, not after a silence with a guess, and
// the script fails as for any early end.
TEST_F(ConsoleE2E, AKilledSimulatorEndsAScriptsRunSayingHow) {
  script_ = dir_.file("killed.nls");
  std::ofstream(script_) << "run 60s label=killed\n";
  const std::string out = dir_.file("console.out");
  const std::string command = "exec " + fmt_command("hasel", "") + " >" + shell_quote(out) + " 2>&1";
  const pid_t pid = test::start_shell(command);
  ASSERT_GT(pid, 0);
  const pid_t sim = simulator_once_recording(pid);
  ASSERT_GT(sim, 0) << "the run never started, or no simulator under the console";
  ASSERT_EQ(run_process("kill -9 " + std::to_string(sim)).code, 0);
  const auto [status, text] = wait_for_console(pid, out);
  ASSERT_NE(status, -1) << "waitpid failed";
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 1) << text;
  EXPECT_NE(text.find("ended early: simulator killed by signal 9 (SIGKILL)"), std::string::npos) << text;
  RunStore store(db());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].end_reason, "ended early: simulator killed by signal 9 (SIGKILL)");
  const auto gaps = store.gaps(runs[0].id);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].reason, "run ended early: simulator killed by signal 9 (SIGKILL)");
}

// The simulator stopped (SIGSTOP) for 4 s of an 8 s run, then continued:
// after 3 s without telemetry the run ends early, and the gap it records is
// the silence it ended in (its frames those that fell due in it), never
// the rest of the run it did not reach: no gap outlasts the run.
TEST_F(ConsoleE2E, AStoppedSimulatorsGapIsTheSilenceNotMoreThanTheRunLasted) {
  script_ = dir_.file("stopped.nls");
  std::ofstream(script_) << "run 8s label=stopped\n";
  const std::string out = dir_.file("console.out");
  const pid_t pid = test::start_shell("exec " + fmt_command("hasel", "") + " >" + shell_quote(out) + " 2>&1");
  ASSERT_GT(pid, 0);
  const pid_t sim = simulator_once_recording(pid);
  ASSERT_GT(sim, 0) << "the run never started, or no simulator under the console";
  ASSERT_EQ(::kill(sim, SIGSTOP), 0);
  std::this_thread::sleep_for(std::chrono::seconds(4));
  ASSERT_EQ(::kill(sim, SIGCONT), 0);
  const auto [status, text] = wait_for_console(pid, out);
  ASSERT_NE(status, -1) << "waitpid failed";
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 1) << text;
  RunStore store(db());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  const RunMetrics m = run_metrics(store, runs[0].id);
  ASSERT_GT(m.wall_s, 0.0);
  const auto gaps = store.gaps(runs[0].id);
  ASSERT_EQ(gaps.size(), 1u) << text;
  const GapRecord& g = gaps[0];
  EXPECT_EQ(g.reason.rfind("run ended early: telemetry stopped arriving", 0), 0u) << g.reason;
  EXPECT_LE(g.duration_s, m.wall_s) << "a silence longer than the run";
  EXPECT_LE(double(g.lost_frames), g.duration_s * runs[0].loop_rate_hz) << "more frames than fell due in the silence";
  EXPECT_LE(double(g.lost_frames) / runs[0].loop_rate_hz, m.wall_s) << "a gap longer than the run";
  EXPECT_EQ(runs[0].lost_frames, g.lost_frames);
}

// The same on the HASEL rig at its own rate, a minute's run under a smaller
// limit: the run is not left unfinished by a killed console.
TEST_F(ConsoleE2E, AFileSizeLimitDuringARunIsReportedNotFatal) {
  script_ = dir_.file("r60.nls");
  std::ofstream(script_) << "run 60s label=r60\n";
  // dash counts 512-byte blocks: 800 is bash's `ulimit -f 400`.
  const auto r = run_process("ulimit -f 800; exec timeout 80 " + fmt_command("hasel", ""));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("run 1 stopped at once: recording failed"), std::string::npos) << r.output;
}

// The terminal closing, or the ssh connection dropping, sends the console
// SIGHUP mid-run: the run is stopped and recorded as ended by it, and the
// console exits 2 saying so, as for Ctrl-C.
TEST_F(ConsoleE2E, AHangupStopsTheRunAndRecordsWhichSignalEndedIt) {
  script_ = dir_.file("long.nls");
  std::ofstream(script_) << "run 600s label=long\n";
  const std::string out = dir_.file("console.out");
  const std::string command = "exec " + fmt_command("msd", "") + " >" + shell_quote(out) + " 2>&1";
  const pid_t pid = test::start_shell(command);
  ASSERT_GT(pid, 0);
  const bool recording = wait_until_recording();
  ASSERT_TRUE(recording) << "the run never started";
  ASSERT_EQ(::kill(pid, SIGHUP), 0);
  const auto [status, text] = wait_for_console(pid, out);
  ASSERT_NE(status, -1) << "waitpid failed";
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 2) << text;
  EXPECT_NE(text.find("interrupted by SIGHUP (the terminal closed or the connection dropped): run 1 stopped and kept"),
            std::string::npos)
      << text;
  RunStore store(db());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_FALSE(runs[0].ended_at.empty()) << "the run was left unfinished";
  EXPECT_EQ(runs[0].end_reason, "interrupted by SIGHUP (the terminal closed or the connection dropped)");
  EXPECT_GT(runs[0].samples, 0u);
}

// A loop that cannot keep its rate (here each step of the simulator takes
// 1.5 ms more at 1 kHz, as a loaded machine makes it) is reported against
// the rate set, at the run's end and by `runs show`, with a warning.
TEST_F(ConsoleE2E, ALoopBelowItsSetRateIsReportedAtTheRunsEndAndByRunsShow) {
  SimLauncher sim;
  const std::string pty = sim.start("msd", {"--step-load-us", "1500"});
  ASSERT_FALSE(pty.empty());
  script_ = dir_.file("slow.nls");
  std::ofstream(script_) << "run 500ms label=slow\n";
  const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + pty + " --db " + shell_quote(db()) +
                             " --script " + shell_quote(script_));
  ASSERT_EQ(r.code, 0) << r.output;
  // "loop 633 Hz of 1 kHz set (63 %)": a step every 1.5 ms at best (slower
  // still on a busy machine, never faster), so at most 67 %.
  auto share = [](const std::string& text) {
    const size_t at = text.find(" of 1 kHz set (");
    return at == std::string::npos ? -1.0 : std::atof(text.c_str() + at + 15);
  };
  const double run_share = share(r.output);
  EXPECT_GT(run_share, 0) << r.output;
  EXPECT_LE(run_share, 67) << r.output;
  EXPECT_NE(r.output.find("warning: the control loop kept"), std::string::npos) << r.output;
  const auto show = run_process(std::string(NLSOFT_CONSOLE_BIN) + " runs show 1 --db " + shell_quote(db()));
  ASSERT_EQ(show.code, 0) << show.output;
  EXPECT_EQ(share(show.output), run_share) << show.output;
  EXPECT_NE(show.output.find("warning: the control loop kept"), std::string::npos) << show.output;
}

// A program that opened the port before the console (`cat /dev/pts/N &`)
// takes bytes meant for it: the console refuses the port and names the
// program, as it names a second console, instead of half-working.
TEST_F(ConsoleE2E, AProgramReadingThePortIsNamedAndThePortRefused) {
  SimLauncher sim;
  const std::string pty = sim.start("msd");
  ASSERT_FALSE(pty.empty());
  const pid_t cat = ::fork();
  ASSERT_GE(cat, 0);
  if (cat == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    ::execlp("cat", "cat", pty.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Until cat has the port open (its /proc fd link names it).
  bool open = false;
  for (int i = 0; i < 200 && !open; ++i) {
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator("/proc/" + std::to_string(cat) + "/fd", ec))
      open |= std::filesystem::read_symlink(e.path(), ec).string() == pty;
    if (!open) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  script_ = dir_.file("s.nls");
  std::ofstream(script_) << "get Q\n";
  const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + pty + " --db " + shell_quote(db()) +
                             " --script " + shell_quote(script_));
  ::kill(cat, SIGTERM);
  ::waitpid(cat, nullptr, 0);
  ASSERT_TRUE(open) << "cat never opened " << pty;
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("port busy: " + pty + " is also open in PID " + std::to_string(cat) + " (cat)"),
            std::string::npos)
      << r.output;
  // With cat gone the port is the console's again (the refusal left no
  // exclusive mode behind).
  const auto after = run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + pty + " --db " + shell_quote(db()) +
                                 " --script " + shell_quote(script_));
  EXPECT_EQ(after.code, 0) << after.output;
  EXPECT_NE(after.output.find("Q = "), std::string::npos) << after.output;
}

// A line that echoes (a loopback: TX wired to RX, or a terminal in echo
// mode at the other end) is named as such, not taken for a silent firmware
// or for frames arriving. The loopback here is a pseudo-terminal whose other
// end sends back every byte.
TEST_F(ConsoleE2E, ALineThatEchoesIsNamedAsSuch) {
  int path_pipe[2];
  ASSERT_EQ(::pipe(path_pipe), 0);
  const pid_t loop = ::fork();
  ASSERT_GE(loop, 0);
  if (loop == 0) {
    const int m = ::posix_openpt(O_RDWR | O_NOCTTY);
    if (m < 0 || ::grantpt(m) != 0 || ::unlockpt(m) != 0) ::_exit(1);
    const std::string name = std::string(::ptsname(m)) + "\n";
    (void)!::write(path_pipe[1], name.data(), name.size());
    ::close(path_pipe[1]);
    uint8_t buf[256];
    while (true) {
      const ssize_t n = ::read(m, buf, sizeof buf);
      if (n > 0) (void)!::write(m, buf, size_t(n));
      else ::usleep(10000);  // EIO while no one has the line open
    }
  }
  ::close(path_pipe[1]);
  std::string line;
  for (char c; ::read(path_pipe[0], &c, 1) == 1 && c != '\n';) line += c;
  ::close(path_pipe[0]);
  script_ = dir_.file("s.nls");
  std::ofstream(script_) << "get Q\n";
  const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + line + " --timeout 50 --db " + shell_quote(db()) +
                             " --script " + shell_quote(script_));
  ::kill(loop, SIGKILL);
  ::waitpid(loop, nullptr, 0);
  ASSERT_FALSE(line.empty());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("the console's own frames came back from " + line), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the line echoes what is sent"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("nothing arrived"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("frames arriving again"), std::string::npos) << r.output;

  // /dev/ptmx itself is a new, empty line at every open: refused in words.
  const auto ptmx = run_process(std::string(NLSOFT_CONSOLE_BIN) + " /dev/ptmx --db " + shell_quote(db()) +
                                " --script " + shell_quote(script_));
  EXPECT_EQ(ptmx.code, 2) << ptmx.output;
  EXPECT_NE(ptmx.output.find("not a serial port: /dev/ptmx makes a new pseudo-terminal at each open"),
            std::string::npos)
      << ptmx.output;
  EXPECT_EQ(ptmx.output.find("frames arriving again"), std::string::npos) << ptmx.output;
}

// The simulator's log lives in a folder of the console's own (0700), not at
// a predictable /tmp name another user could plant a link at, and goes away
// with the launcher.
TEST_F(ConsoleE2E, SimulatorLogIsPrivateAndRemoved) {
  std::string dir;
  {
    nlsoft::console::SimLauncher sim;
    const std::string pty = sim.start("msd");
    ASSERT_FALSE(pty.empty());
    dir = std::filesystem::path(sim.log_path()).parent_path().string();
    EXPECT_EQ(dir.rfind("/tmp/nlsoft-sim.", 0), 0u) << dir;
    struct stat st {};
    ASSERT_EQ(::stat(dir.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0700u);
    ASSERT_EQ(::lstat(sim.log_path().c_str(), &st), 0);
    EXPECT_TRUE(S_ISREG(st.st_mode));
  }
  EXPECT_FALSE(std::filesystem::exists(dir));
}

// SETTINGS (PROTOCOL.md 9.11): a parameter kept with `settings save` is in
// force when the next console starts the simulator again with the same
// database (its settings file is beside it), `settings defaults` brings the
// built-in value back, and a simulator that keeps no settings is refused
// in words before anything runs.
TEST_F(ConsoleE2E, SavedSettingsSurviveTheSimulatorAndDefaultsBringTheBuiltInBack) {
  auto r = run_script("set Lambda 0.5\nsettings save\n", "msd");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("settings saved: the firmware starts with the parameters in force from now on"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("settings: built-in (nothing saved)"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(db() + ".msd.settings")) << db() + ".msd.settings";
  r = run_script("get Lambda\nsettings defaults\nget Lambda\n", "msd");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("settings: from flash, save 1 ("), std::string::npos) << r.output;
  const size_t saved = r.output.find("Lambda = 0.5");
  ASSERT_NE(saved, std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Lambda = 0.04", saved), std::string::npos) << r.output;  // msd's built-in Lambda
  r = run_script("get Lambda\n", "msd");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("settings: built-in (restored by request)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Lambda = 0.04"), std::string::npos) << r.output;

  r = run_script("set Lambda 0.5\nsettings save\n", "msd", "--sim-settings none");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("keeps no settings: it has no SETTINGS capability"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("Lambda = 0.5"), std::string::npos) << "the script ran: " << r.output;
  r = run_script("settings keep\n", "msd");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("'settings keep': say settings save"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace nlsoft::console
