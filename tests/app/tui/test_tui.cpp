// The TUI as a person uses it: nlsoft-console --sim hasel runs inside tmux,
// keys are sent, and the screen is read back with capture-pane. Skipped,
// saying why, when tmux is not installed.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include "app/link/sim_launcher.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sqlite.hpp"
#include "app/record/tune_log.hpp"
#include "app/support/process_tree.hpp"
#include "app/support/tmux_console.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::slurp;

using namespace tui_test;

using test::descendant_named;
using test::run_process;
using test::shell_quote;

bool has_braille(const std::string& s) {
  // U+2801..U+28FF in UTF-8: E2 A0 81 .. E2 A3 BF
  for (size_t i = 0; i + 2 < s.size(); ++i)
    if (uint8_t(s[i]) == 0xE2 && (uint8_t(s[i + 1]) & 0xFC) == 0xA0 && !(uint8_t(s[i + 1]) == 0xA0 && uint8_t(s[i + 2]) == 0x80))
      return true;
  return false;
}

TEST(ConsoleTui, PlotsDrawAndAnEditedParameterShowsApplied) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string db = dir.file("runs.db");
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + db,
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  EXPECT_TRUE(contains(s, "F1Help")) << s;
  EXPECT_TRUE(contains(s, "link up")) << s;

  t.keys("F5");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "RUNNING") && has_braille(x); }, s)) << s;
  EXPECT_TRUE(contains(s, "y0  \u2501 ref ")) << s;
  EXPECT_TRUE(contains(line_with(s, "y0  \u2501 ref "), "\u2501 hat ")) << s;
  EXPECT_TRUE(contains(line_with(s, "y0  \u2501 ref "), "\u2501 true ")) << s;

  // Down to r (Q, Lambda, s, b, r), edit in place, type 500.
  t.keys("Down Down Down Down Enter C-u 500 Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(param_row(x, "r"), "500 u applied"); }, s)) << s;

  // A value the firmware refuses shows its reason and changes nothing.
  t.keys("Enter C-u -1 Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(param_row(x, "r"), "refused"); }, s)) << s;
  EXPECT_TRUE(contains(param_row(s, "r"), "refused: r = -1")) << s;
  EXPECT_TRUE(contains(s, "r: r = -1 is out of range [1e-06, 1e+07]")) << s;  // the message line has room
  EXPECT_TRUE(contains(param_row(s, "r"), "500 u")) << s;

  t.keys("F6");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stopped:"); }, s)) << s;
  t.keys("q");
  std::string last;
  for (int i = 0; i < 50 && t.alive(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(t.alive()) << "q should quit when no run is active";

  RunStore store(db);
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_GT(runs[0].samples, 0u);
  bool logged = false;
  for (const auto& p : store.params(runs[0].id)) logged |= !p.at_start && p.name == "r" && p.value == "500";
  EXPECT_TRUE(logged) << "the edit is recorded with its time in the run";
}

TEST(ConsoleTui, AsciiFallbackAndResize) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim msd --no-record",
         "LANG=C LC_ALL=C NO_COLOR=1 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "Parameters ("); }, s)) << s;
  t.keys("F5");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "RUNNING") && contains(x, "y0  . ref ") && contains(x, " + hat ") && contains(x, " * true "); }, s)) << s;
  EXPECT_FALSE(has_braille(s)) << s;
  t.resize(50, 12);
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "terminal too small"); }, s)) << s;
  t.resize(100, 30);
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "F1Help"); }, s)) << s;
  t.keys("q");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stop it and quit?"); }, s)) << s;
  t.keys("y");
  for (int i = 0; i < 50 && t.alive(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(t.alive());
}

// Quitting while a `:run` from the command line is going: the worker that
// waits in run_for is stopped and joined before anything it uses is
// destroyed (it was a heap-use-after-free of the message log), and the quit
// does not wait for the run's deadline. The exit status is the console's
// own, so under ASan/UBSan (abort) or TSan (exit 66) a report fails here.
TEST(ConsoleTui, QuitDuringATimedRunExitsCleanlyAndKeepsTheRun) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string db = dir.file("runs.db"), status = dir.file("status"), err = dir.file("stderr");
  Tmux t("sh -c " + shell_quote(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + shell_quote(db) + " 2>" +
                                shell_quote(err) + "; echo $? >" + shell_quote(status)),
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  // A run far longer than the test: it can only end through the quit.
  t.keys(shell_quote(":run 60s") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "RUNNING") && contains(x, "[run 60s"); }, s))
      << s;
  t.keys("q");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stop it and quit?"); }, s)) << s;
  t.keys("y");
  // Bounded poll for the exit; the bound is generous for sanitizer builds
  // and far below the 60 s run the console would otherwise wait out.
  for (int i = 0; i < 300 && !std::filesystem::exists(status); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(std::filesystem::exists(status)) << "the console did not exit after q, y during a timed run\n"
                                               << t.screen() << slurp(err);
  // `echo` may not have flushed the digits when the file first appears.
  std::string code;
  for (int i = 0; i < 100 && (code = slurp(status)).find('\n') == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(code, "0\n") << slurp(err);

  RunStore store(db);
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_FALSE(runs[0].ended_at.empty()) << "the run is closed, not left unfinished";
  EXPECT_GT(runs[0].samples, 0u);
}

// `:ident` from the command line at 80x24: the plot turns to the run's
// inputs, measured outputs and sensors, the message line counts its steps,
// and F6 stops it early keeping what was recorded, as an identification run.
TEST(ConsoleTui, IdentPlotsInputsOutputsAndSensorsAndF6KeepsTheRun) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string db = dir.file("runs.db");
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + shell_quote(db),
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN, 80, 24);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  // At 24 rows the panel shows the parameters down to u_max.
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "Parameters (") && contains(x, "u_max"); }, s))
      << s;
  // Far longer than the test: only F6 ends it.
  t.keys(shell_quote(":ident prbs 120s seed=3") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "[ident prbs: ") && has_braille(x); }, s, 30))
      << s;
  // Three strips: the inputs, the measured outputs, the sensors.
  EXPECT_TRUE(contains(s, "u  \u2501 u0 ")) << s;
  EXPECT_TRUE(contains(s, "y  \u2501 y0 ")) << s;
  EXPECT_TRUE(contains(s, "l  \u2501 l0 ")) << s;
  EXPECT_TRUE(contains(s, " ident | window")) << s;
  EXPECT_TRUE(contains(line_with(s, "[ident prbs: "), " steps, ")) << s;
  t.keys("F6");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "run 1 (ident prbs seed 3 120s): ") && !contains(x, "[ident"); },
                         s, 30))
      << s;
  RunStore store(db);
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].kind, "ident");
  EXPECT_EQ(runs[0].label, "ident prbs seed 3 120s");
  EXPECT_FALSE(runs[0].ended_at.empty()) << "the run is closed, not left unfinished";
  EXPECT_GT(runs[0].samples, 0u);
  EXPECT_LT(runs[0].samples, 120u * 130u) << "stopped early";
  const RunSeries series = store.series(runs[0].id);
  EXPECT_EQ(series.rows(), runs[0].samples);
  EXPECT_TRUE(series.has_u && series.has_y_true && series.has_l);
  t.keys("q");
}

// Ctrl-C during a `:ident`: the console ends, the identification run
// stopped and kept with the signal named as its end.
TEST(ConsoleTui, CtrlCDuringIdentKeepsTheRun) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string db = dir.file("runs.db"), status = dir.file("status");
  // The shell traps SIGINT with a handler (the console gets the default
  // back at exec) so it lives on to write the console's status.
  Tmux t("sh -c " + shell_quote("trap true INT; " + std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " +
                                shell_quote(db) + " 2>/dev/null; echo $? >" + shell_quote(status)),
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys(shell_quote(":ident walk 120s") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "[ident walk: ") && has_braille(x); }, s, 30))
      << s;
  t.keys("C-c");
  for (int i = 0; i < 300 && !std::filesystem::exists(status); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(std::filesystem::exists(status)) << "the console did not exit after Ctrl-C during :ident\n" << t.screen();
  std::ifstream status_in(status);
  std::string code;
  std::getline(status_in, code);
  EXPECT_EQ(code, "0") << "the console's exit status after Ctrl-C (a sanitizer's report ends it with 66)";
  RunStore store(db);
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].kind, "ident");
  EXPECT_FALSE(runs[0].ended_at.empty()) << "the run is closed, not left unfinished";
  EXPECT_NE(runs[0].end_reason.find("SIGINT"), std::string::npos) << runs[0].end_reason;
  EXPECT_GT(runs[0].samples, 0u);
}

// A recorded run without a measured output (its y_true taken out of the
// database): the runs panel's metrics say they are the model's prediction.
TEST(ConsoleTui, TheRunsPanelSaysARunHasNoMeasuredOutput) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string db = dir.file("runs.db"), script = dir.file("r.nls");
  std::ofstream(script) << "ref infinity\nrun 1s\n";
  const auto rec = run_process("env NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN " " + std::string(NLSOFT_CONSOLE_BIN) +
                               " --sim hasel --db " + shell_quote(db) + " --script " + shell_quote(script));
  ASSERT_EQ(rec.code, 0) << rec.output;
  {
    Db file(db, Db::Access::ReadWrite);
    file.exec("UPDATE samples SET y_true=NULL");
  }
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + shell_quote(db),
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys("F4");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " Runs ("); }, s)) << s;
  t.keys("Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "no measured output: tracking"); }, s)) << s;
  t.keys("q");
}

// The simulator killed with -9 under the TUI mid-run: the console says how
// it ended instead of staying RUNNING / LINK DOWN, ends the run with that
// reason and the gap since its last sample (in the database too), shows R
// Restart on the key bar, and R starts a new simulator it reconnects to.
TEST(ConsoleTui, AKilledSimulatorIsNamedItsRunEndedAndRRestartsIt) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string db = dir.file("runs.db");
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + db,
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  EXPECT_FALSE(contains(s, "RRestart")) << s;
  t.keys("F5");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "run 1 RUNNING") && has_braille(x); }, s)) << s;
  const pid_t sim = descendant_named(t.pane_pid(), "nlsoft-firmware-sim");
  ASSERT_GT(sim, 0) << "no simulator under the console";
  ASSERT_EQ(run_process("kill -9 " + std::to_string(sim)).code, 0);
  // "ended and kept" is said once the run's end is in the database: the
  // first words on the kill come before (stress run 6 of 75b60af read the
  // database between the two and found the run unfinished).
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(x, "simulator killed by signal 9 (SIGKILL)") && contains(x, "no run") && contains(x, "RRestart") &&
           contains(x, "run 1 ended and kept");
  }, s)) << s;
  {
    RunStore store(db);
    const auto runs = store.list();
    ASSERT_EQ(runs.size(), 1u);
    EXPECT_FALSE(runs[0].ended_at.empty()) << "the run was left unfinished";
    EXPECT_EQ(runs[0].end_reason, "simulator killed by signal 9 (SIGKILL)");
    EXPECT_GT(runs[0].samples, 0u);
    const auto gaps = store.gaps(runs[0].id);
    ASSERT_EQ(gaps.size(), 1u);
    EXPECT_EQ(gaps[0].reason, "simulator killed by signal 9 (SIGKILL)");
    EXPECT_GT(gaps[0].duration_s, 0.0);
    EXPECT_EQ(gaps[0].after_k + 1, runs[0].samples) << "the gap follows the last sample";
  }

  t.keys("R");
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(x, "simulator restarted on") && contains(x, "link up") && !contains(x, "RRestart");
  }, s)) << s;
  const pid_t again = descendant_named(t.pane_pid(), "nlsoft-firmware-sim");
  EXPECT_GT(again, 0);
  EXPECT_NE(again, sim);
  t.keys("F5");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "run 2 RUNNING") && has_braille(x); }, s)) << s;
  t.keys("F6");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "run 2 stopped:"); }, s)) << s;
  t.keys("q");
  for (int i = 0; i < 50 && t.alive(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(t.alive());
  RunStore store(db);
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_GT(runs[1].samples, 0u) << "the restarted simulator's run recorded nothing";
}

// A board that reset behind a reconnect: the panel re-reads the values,
// marks the row the reset changed (never "applied" with an old value), and
// A sends the session's edit again. The port is a link the test re-points
// to a freshly started firmware, as a board reset looks to the console.
TEST(ConsoleTui, AFirmwareResetIsMarkedInThePanelAndAReappliesTheEdits) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  test::TempDir dir;
  auto first = std::make_unique<SimLauncher>();
  const std::string board = dir.file("board");
  ASSERT_EQ(::symlink(first->start("hasel").c_str(), board.c_str()), 0);
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " " + board + " --db " + dir.file("runs.db"), "LANG=C.UTF-8 LC_ALL=C.UTF-8");
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys("Down Down Down Down Enter C-u 500 Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(param_row(x, "r"), "500 u applied"); }, s)) << s;
  // The second firmware boots well after the first (the console allows
  // half a second of latency in its boot-time estimate).
  std::this_thread::sleep_for(std::chrono::seconds(2));
  // The link goes first: the dead firmware's pty may be anyone's next.
  ASSERT_EQ(::unlink(board.c_str()), 0);
  first.reset();
  SimLauncher second;
  ASSERT_EQ(::symlink(second.start("hasel").c_str(), board.c_str()), 0);
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(param_row(x, "r"), "reset, was 500"); },
                         s, 30))
      << s;
  EXPECT_FALSE(contains(param_row(s, "r"), "500 u applied")) << s;
  EXPECT_FALSE(contains(param_row(s, "r"), "applied")) << s;
  t.keys("A");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "1 edit sent again"); }, s)) << s;
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(param_row(x, "r"), "500 u") &&
                                                           !contains(param_row(x, "r"), "reset, was"); },
                         s))
      << s;
  t.keys("q");
}

// Tuning needs the quantities the knobs act on: u for every actuator, the
// cost, the Newton iterations and the compute time, chosen with p or :plot;
// without colour each trace has its own glyph, named in a legend that reads
// out its value; the time axis is labelled in seconds; Space freezes the
// view while the run records on, [ scrolls back, + zooms in.
TEST(ConsoleTui, PlotSignalsWithoutColourPauseScrollAndZoom) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + dir.file("runs.db"),
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NO_COLOR=1 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys("F5");
  // Monochrome: glyphs, not look-alike braille, and each with its value.
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(x, "RUNNING") && contains(x, "y0  . ref ") && contains(x, " + hat ") && contains(x, " * true ") &&
           contains(line_with(x, "y0  . ref"), "err ");
  }, s)) << s;
  EXPECT_TRUE(contains(s, " y | window 10 s | live")) << s;
  // The time axis: seconds of the run under the plots.
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "0s") && contains(x, "2s"); }, s)) << s;

  t.keys("p");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " u | window") && contains(x, "u5 "); }, s)) << s;
  EXPECT_TRUE(contains(s, "u0 ")) << s;
  for (const auto& [name, legend] : std::vector<std::pair<std::string, std::string>>{
           {"cost", "cost  "}, {"iter", "iterations "}, {"compute", "us/step "}}) {
    t.keys(shell_quote(":plot " + name) + " Enter");
    const std::string status = " " + name + " | window";
    ASSERT_TRUE(t.wait_for([&](const std::string& x) { return contains(x, status) && contains(x, legend); }, s))
        << name << "\n" << s;
  }
  t.keys(shell_quote(":plot J") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(x, "plot: 'J' is not a signal; use y, u, cost, iter, compute or ident");
  }, s)) << s;
  t.keys(shell_quote(":plot y") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " y | window 10 s"); }, s)) << s;

  t.keys("+");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "window 5 s"); }, s)) << s;

  // Paused: the readout holds still while the run goes on recording.
  t.keys("Space");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "PAUSED at "); }, s)) << s;
  const std::string frozen = line_with(s, "y0  . ref");
  const std::string paused_at = line_with(s, "PAUSED at ");
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  s = t.screen();
  EXPECT_EQ(line_with(s, "y0  . ref"), frozen) << s;
  EXPECT_TRUE(contains(s, "RUNNING")) << s;
  // The time cursor: the readout follows it, the status line says where.
  const std::string edge_readout = line_with(s, "y0  . ref");
  t.keys("'<'");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, ", cursor "); }, s)) << s;
  const std::string first_cursor = line_with(s, ", cursor ");
  t.keys("'<' '<' '<' '<' '<' '<' '<' '<' '<' '<'");
  ASSERT_TRUE(t.wait_for([&](const std::string& x) {
    return contains(x, ", cursor ") && line_with(x, ", cursor ") != first_cursor;
  }, s)) << s;
  EXPECT_NE(line_with(s, "y0  . ref"), edge_readout) << "the readout reads at the cursor\n" << s;
  // "PAUSED at 3.99 s": the right edge's time.
  auto edge = [](const std::string& x) {
    const std::string l = line_with(x, "PAUSED at ");
    return l.substr(l.find("PAUSED at "), l.find(" s") - l.find("PAUSED at "));
  };
  t.keys("[");
  ASSERT_TRUE(t.wait_for([&](const std::string& x) {
    return contains(x, "PAUSED at ") && edge(x) != edge(paused_at);
  }, s)) << s;
  t.keys("Space");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "| live"); }, s)) << s;
  t.keys("F6");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stopped:"); }, s)) << s;
  t.keys("q");
}

// A run longer than the console keeps in memory (16384 samples) can be
// scrolled through whole: going back past the oldest sample kept reads the
// earlier ones from the database.
TEST(ConsoleTui, ScrollingBackPastMemoryReadsTheRunFromTheDatabase) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --sim-fast --db " + dir.file("runs.db"),
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  // 300 s of 130 Hz steps: 39000 samples, the first 22616 only on disk.
  t.keys(shell_quote(":run 300s") + " Enter");
  // A bound, not a timing: under a sanitizer on a loaded machine 39000 steps take minutes.
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "run 1: ") && contains(x, " samples"); }, s, 240))
      << s;
  t.keys("Space");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "PAUSED at "); }, s)) << s;
  // Half a window a key: 40 keys cover 20 windows, past the 16384 kept.
  for (int i = 0; i < 4; ++i) t.keys("'[' '[' '[' '[' '[' '[' '[' '[' '[' '['");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "older samples of run 1 read from the database"); },
                         s))
      << s;
  // The first read is a memory's worth; the rest of the run comes with more keys.
  t.keys("F9");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "16384 older samples of run 1"); }, s)) << s;
  auto reads = [](const std::string& x) {
    size_t n = 0;
    for (size_t at = x.find("older samples of run 1"); at != std::string::npos; at = x.find("older samples of run 1", at + 1)) ++n;
    return n;
  };
  for (int i = 0; i < 6; ++i) t.keys("'[' '[' '[' '[' '[' '[' '[' '[' '[' '['");
  ASSERT_TRUE(t.wait_for([&](const std::string& x) { return reads(x) >= 2; }, s)) << s;
  t.keys("q");
}

// The selected parameter explains itself before anything is sent: what it
// does, its range and unit, or its options; options go by name, one value
// sets every element, and a refusal is shown whole.
TEST(ConsoleTui, ParametersExplainThemselvesAndTakeNamesAndOneValueForAll) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + dir.file("runs.db"),
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "Q: tracking weight per output"); }, s)) << s;
  t.keys("Down");
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(x, "Lambda: weight on input changes") && contains(x, "range [0, 1e+12] 1/u^2, 6 values");
  }, s)) << s;

  t.keys(shell_quote(":set Lambda 0.5") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(param_row(x, "Lambda"), "0.5 0.5 0.5 0.5 0.5 0.5");
  }, s)) << s;
  t.keys(shell_quote(":set mode fd") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(param_row(x, "mode"), "1 (fd)"); }, s)) << s;
  t.keys(shell_quote(":set safe_state hold") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(param_row(x, "safe_state"), "0 (hold)"); }, s))
      << s;
  t.keys(shell_quote(":set feedback sideways") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(x, "feedback: 'sideways' is not an option; use predicted (0), measured (1)");
  }, s)) << s;

  // Down to r; the range is on screen before anything is typed.
  t.keys("Down Down Down");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "range [1e-06, 1e+07] u"); }, s)) << s;
  t.keys("Enter C-u -1 Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(x, "refused: r = -1 is out of range [1e-06, 1e+07]") && contains(param_row(x, "r"), "refused");
  }, s)) << s;

  // F9: every message of the session with its time, and the same in a log
  // file beside the database.
  t.keys("F9");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " Messages (") && contains(x, "connected to nlsoft-posix"); },
                         s))
      << s;
  const std::string connected = line_with(s, "connected to nlsoft-posix");
  EXPECT_EQ(connected.find(':', connected.find("connected") - 9), connected.find("connected") - 7) << connected;
  EXPECT_TRUE(contains(s, "Lambda = 0.5 0.5 0.5 0.5 0.5 0.5")) << s;
  t.keys("q");
  for (int i = 0; i < 50 && t.alive(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const std::string log = slurp(dir.file("runs.session.log"));
  EXPECT_TRUE(contains(log, "connected to nlsoft-posix")) << log;
  EXPECT_TRUE(contains(log, "error r: r = -1 is out of range")) << log;
}

// The help overlay wraps to an 80-column terminal, and the key that closes
// it still does its job (p changes the plot) unless it only means "close".
TEST(ConsoleTui, HelpFitsEightyColumnsAndClosingItKeepsTheKey) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --no-record",
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  t.resize(80, 40);
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys("?");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "nlsoft-console keys"); }, s)) << s;
  // The reference line's end, past column 80 unwrapped, is on the next page.
  t.keys("PageDown");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "hold levels"); }, s)) << s;
  t.keys("Escape");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return !contains(x, "-- lines "); }, s)) << s;
  EXPECT_TRUE(contains(s, " y | window")) << "Escape only closes\n" << s;
  t.keys("?");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "nlsoft-console keys"); }, s)) << s;
  t.keys("p");
  // Tab at the ':' line: a parameter completed, an ambiguous command listed.
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " u | window"); }, s)) << s;
  t.keys(shell_quote(":set Lam") + " Tab");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, ":set Lambda"); }, s)) << s;
  t.keys("C-u s Tab");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, ":s   [set start stop settings sweep]"); }, s)) << s;
  t.keys("Escape");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return !contains(x, "nlsoft-console keys") && contains(x, " u | window"); },
                         s))
      << s;
  // 24 rows: the help does not fit; it says so and scrolls to its last
  // lines (tune's, whose replay= line ends it).
  t.resize(80, 24);
  t.keys("?");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "nlsoft-console keys") && contains(x, "-- lines 1-"); },
                         s))
      << s;
  EXPECT_FALSE(contains(s, "untouched;")) << s;
  t.keys("End");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "untouched;"); }, s)) << s;
  EXPECT_FALSE(contains(s, "nlsoft-console keys")) << "scrolled past the title\n" << s;
  t.keys("PageUp");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return !contains(x, "untouched;") && contains(x, "-- lines "); },
                         s))
      << s;
  t.keys("Escape");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return !contains(x, "-- lines "); }, s)) << s;
  t.keys("q");
}

// `:model upload FILE` from the TUI: the new model is confirmed by its hash
// on the message line; a file the firmware could not run is refused there.
TEST(ConsoleTui, AModelUploadedFromTheCommandLineIsConfirmedByItsHash) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string model = dir.file("hasel.nlsm");
  std::filesystem::copy_file(std::string(NLSOFT_SOURCE_MODELS_DIR) + "/hasel.nlsm", model);
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --no-record",
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys(shell_quote(":model upload " + model) + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " confirmed (was "); }, s)) << s;
  t.keys(shell_quote(":model upload " + dir.file("none.nlsm")) + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "none.nlsm: cannot read"); }, s)) << s;
  t.keys("q");
}

// A recorded run under the live one: `:overlay 1` adds it to each y strip
// as its own trace, named in the legend; `:overlay off` removes it.
TEST(ConsoleTui, ARecordedRunOverlaysTheLivePlot) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + dir.file("runs.db"),
         "LANG=C LC_ALL=C NO_COLOR=1 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys(shell_quote(":run 1s") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "run 1: ") && !contains(x, "RUNNING"); }, s)) << s;
  t.keys(shell_quote(":overlay 9") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "overlay: no run 9"); }, s)) << s;
  t.keys(shell_quote(":overlay 1") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "overlay: run 1 under the live plot"); }, s)) << s;
  t.keys("F5");
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(x, "run 2 RUNNING") && contains(line_with(x, "y0  . ref"), "o run 1");
  }, s)) << s;
  t.keys(shell_quote(":overlay off") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return contains(x, "overlay removed") && !contains(line_with(x, "y0  . ref"), "o run 1");
  }, s)) << s;
  t.keys("F6");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stopped:"); }, s)) << s;
  t.keys("q");
}

}  // namespace
}  // namespace nlsoft::console

namespace nlsoft::console {
namespace {

using namespace tui_test;

// `:tune` from the command line: the convergence view appears under the
// plot with the evaluation count and the best so far, the best set is
// saved, and t hides the view.
TEST(ConsoleTui, TuneShowsItsConvergenceUnderThePlot) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string saved = dir.file("tui.params");
  Tmux t(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + dir.file("runs.db"),
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys(shell_quote(":tune Lambda=0.1..10:log budget=3 settle=0 window=1s reference=\"swirl hold=1\" save=" + saved) +
         " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " tune: eval 1/3"); }, s, 30)) << s;
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "best set saved to"); }, s, 60)) << s;
  EXPECT_TRUE(contains(s, " tune: eval 3/3  best ")) << s;
  EXPECT_TRUE(contains(line_with(s, " tune: eval 3/3"), "Lambda=")) << s;
  EXPECT_TRUE(std::ifstream(saved).good());
  t.keys("t");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return !contains(x, " tune: eval"); }, s)) << s;
  t.keys("q");
}

// Quitting during a :tune: the worker's session is cancelled (the run in
// progress stopped and kept), the parameters are put back, the best so far
// is saved, and the console exits 0 with the session closed in the database.
TEST(ConsoleTui, QuitDuringATuneSavesTheBestAndExitsCleanly) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string db = dir.file("runs.db"), status = dir.file("status"), err = dir.file("stderr"),
                    saved = dir.file("q.params");
  Tmux t("sh -c " + shell_quote(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + shell_quote(db) + " 2>" +
                                shell_quote(err) + "; echo $? >" + shell_quote(status)),
         "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys(shell_quote(":tune Lambda=0.1..10:log budget=40 settle=0 window=1s reference=\"swirl hold=1\" save=" + saved) +
         " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " tune: eval 1/40"); }, s, 30)) << s;
  t.keys("q");
  // Between two runs q quits at once; during one it asks first.
  for (int i = 0; i < 300 && !std::filesystem::exists(status); ++i) {
    if (contains(t.screen(), "stop it and quit?")) t.keys("y");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(std::filesystem::exists(status)) << "the console did not exit after q during a tune\n"
                                               << t.screen() << slurp(err);
  std::string code;
  for (int i = 0; i < 100 && (code = slurp(status)).find('\n') == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(code, "0\n") << slurp(err);
  EXPECT_TRUE(contains(slurp(saved), "Lambda ")) << "the best so far is saved";
  const auto sessions = tune_sessions(db);
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].end_reason, "cancelled");
  RunStore store(db);
  for (const RunRow& r : store.list()) EXPECT_FALSE(r.ended_at.empty()) << "run " << r.id << " left open";
}

}  // namespace
}  // namespace nlsoft::console

namespace nlsoft::console {
namespace {

using namespace tui_test;

// A line's cells: one UTF-8 code point each (the screen has no wide ones).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  for (size_t i = 0; i < line.size();) {
    const unsigned char c = static_cast<unsigned char>(line[i]);
    const size_t len = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : 4;
    out.push_back(line.substr(i, len));
    i += len;
  }
  return out;
}

// The column where `what` starts on the line, or -1.
int column_of(const std::string& line, const std::string& what) {
  const size_t at = line.find(what);
  return at == std::string::npos ? -1 : int(cells(line.substr(0, at)).size());
}

// The rightmost column holding a braille dot on any of the lines [from, to).
int rightmost_braille(const std::string& screen, size_t from, size_t to) {
  const auto lines = screen_lines(screen);
  int right = -1;
  for (size_t r = from; r < to && r < lines.size(); ++r) {
    const auto cs = cells(lines[r]);
    for (size_t c = 0; c < cs.size(); ++c)
      if (has_braille(cs[c] + "  ")) right = std::max(right, int(c));
  }
  return right;
}

// Rows of the screen, from `margin` rows above the one holding `first` to
// `margin` rows below the one holding `last`, that show a braille dot (a
// plot drawn through or against an overlay).
std::vector<std::string> rows_with_dots_between(const std::string& screen, const std::string& first,
                                                const std::string& last, int margin = 0) {
  const auto lines = screen_lines(screen);
  int top = -1, bottom = -1;
  for (int i = 0; i < int(lines.size()); ++i) {
    if (top < 0 && contains(lines[size_t(i)], first)) top = i;
    if (top >= 0 && contains(lines[size_t(i)], last)) {
      bottom = i;
      break;
    }
  }
  if (top < 0 || bottom < 0) return {"(no overlay from '" + first + "' to '" + last + "')"};
  std::vector<std::string> out;
  for (int i = std::max(0, top - margin); i <= bottom + margin && i < int(lines.size()); ++i)
    if (has_braille(lines[size_t(i)] + "  ")) out.push_back(lines[size_t(i)]);
  return out;
}

// Whether `word` on the screen (captured with its attributes) is drawn as
// the selection: the last attribute set before it is reverse video (7) or
// the selection's blue background (44).
bool highlighted(const std::string& escaped, const std::string& word) {
  const size_t at = escaped.find(word);
  if (at == std::string::npos) return false;
  const size_t esc = escaped.rfind("\x1b[", at);
  const size_t line = escaped.rfind('\n', at);
  if (esc == std::string::npos || (line != std::string::npos && esc < line)) return false;
  const std::string params = escaped.substr(esc + 2, escaped.find('m', esc) - esc - 2);
  std::istringstream in(params);
  for (std::string p; std::getline(in, p, ';');)
    if (p == "7" || p == "44") return true;
  return false;
}

// 80x24, the size a terminal opens at: the plot gets most of the width (a
// narrow parameter panel) and every key of the key bar shows.
TEST(ConsoleTui, AtEightyByTwentyFourThePlotHasMostOfTheWidthAndEveryKeyShows) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  Tmux t = console_in("--sim hasel --no-record", 80, 24);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_for(panel_read, s)) << s;
  const auto lines = screen_lines(s);
  ASSERT_EQ(lines.size(), 24u) << s;
  for (const char* key : {"F1Help", "F2Par", "F3Ref", "F4Runs", "F5Start", "F6Stop", "F7Hold", "F8Neut", ":Cmd",
                          "vView", "wPanel", "qQuit"})
    EXPECT_TRUE(contains(lines[23], key)) << key << " is not on the key bar\n" << s;
  // The panel starts right of column 48: the plot pane has 3/5 of the width.
  const int panel = column_of(line_with(s, " Parameters ("), " Parameters (");
  EXPECT_GE(panel, 48) << s;
  EXPECT_TRUE(contains(s, " Lambda  1 1 1 1 1 1")) << "a short name, then the values\n" << s;
  t.keys("F5");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "RUNNING") && rightmost_braille(x, 1, 20) >= 44; },
                         s))
      << s;
  EXPECT_LT(rightmost_braille(s, 1, 20), panel) << s;
  t.keys("q y");
}

// 160x48: the htop-style key bar with whole labels, the wide panel with
// whole names.
TEST(ConsoleTui, AtOneSixtyByFortyEightTheKeyBarAndThePanelHaveWholeWords) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  Tmux t = console_in("--sim hasel --no-record", 160, 48);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  const auto lines = screen_lines(s);
  ASSERT_EQ(lines.size(), 48u) << s;
  for (const char* key : {"F1Help   ", "F2Params ", "F8Neutral", ":Cmd    ", "vView   ", "wPanel  ", "qQuit"})
    EXPECT_TRUE(contains(lines[47], key)) << key << "\n" << s;
  EXPECT_GE(column_of(line_with(s, " Parameters ("), " Parameters ("), 90) << s;
  EXPECT_TRUE(contains(param_row(s, "nr_max_iter"), "nr_max_iter")) << "whole names in the wide panel\n" << s;
  t.keys("q");
}

// w hides the side panel, the plot then takes the whole width; w again, or
// a panel's key, brings it back. The help names the key.
TEST(ConsoleTui, WHidesTheSidePanelForAPlotAcrossTheWholeWidth) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  Tmux t = console_in("--sim hasel --no-record", 80, 24);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_for(panel_read, s)) << s;
  t.keys("F5");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "RUNNING") && has_braille(x); }, s)) << s;
  t.keys("w");
  ASSERT_TRUE(t.wait_for([](const std::string& x) {
    return !contains(x, "Parameters (") && rightmost_braille(x, 1, 20) >= 72;
  }, s)) << s;
  t.keys("w");
  ASSERT_TRUE(t.wait_for(panel_read, s)) << s;
  t.keys("w");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return !contains(x, "Parameters ("); }, s)) << s;
  t.keys("F4");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, " Runs ("); }, s)) << s;
  t.keys("?");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "hide / show the side panel"); }, s)) << s;
  t.keys("Escape q y");
}

// The help and the quit dialog hide the plot under them: the help is drawn
// over nothing (no plot beside it either, on a wide terminal), the dialog
// with a blank row above and below.
TEST(ConsoleTui, TheHelpAndTheQuitDialogShowNoPlotThroughThem) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  Tmux t = console_in("--sim hasel --no-record", 160, 48);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_until_connected(s)) << s;
  t.keys("F5");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "run 1 RUNNING") && has_braille(x); }, s)) << s;
  t.keys("?");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "nlsoft-console keys"); }, s)) << s;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // several redraws with the plot moving under it
  s = t.screen();
  EXPECT_FALSE(has_braille(s)) << s;
  t.keys("Escape");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return !contains(x, "nlsoft-console keys") && has_braille(x); }, s))
      << s;
  t.resize(80, 24);
  t.keys("q");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stop it and quit?"); }, s)) << s;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  s = t.screen();
  EXPECT_EQ(screen_lines(s).size(), 24u) << s;
  EXPECT_EQ(rows_with_dots_between(s, "stop it and quit?", "y: yes", 1), std::vector<std::string>{}) << s;
  t.keys("y");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "EXIT="); }, s)) << s;
  EXPECT_EQ(quit_status(s), "EXIT=0") << s;
}

// F3 opens on the reference in force: the hasel firmware starts on its
// paper task, Swirl; after `:ref diagonal` it is Diagonal.
TEST(ConsoleTui, F3OpensOnTheReferenceInForce) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  Tmux t = console_in("--sim hasel --no-record", 80, 24);
  ASSERT_TRUE(t.started()) << t.error();
  std::string s;
  ASSERT_TRUE(t.wait_for(panel_read, s)) << s;
  t.keys("F3");
  ASSERT_TRUE(t.wait_for([&](const std::string& x) {
    return contains(x, "in force: swirl") && highlighted(t.screen_with_attributes(), " Swirl ");
  }, s)) << t.screen_with_attributes();
  EXPECT_FALSE(highlighted(t.screen_with_attributes(), " Infinity ")) << t.screen_with_attributes();
  t.keys("F2 " + shell_quote(":ref diagonal") + " Enter");
  ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "reference diagonal in force"); }, s)) << s;
  t.keys("F3");
  ASSERT_TRUE(t.wait_for([&](const std::string& x) {
    return contains(x, "in force: diagonal") && highlighted(t.screen_with_attributes(), " Diagonal ");
  }, s)) << t.screen_with_attributes();
  EXPECT_FALSE(highlighted(t.screen_with_attributes(), " Swirl ")) << t.screen_with_attributes();
  t.keys("q");
}

// On exit, on the normal screen: the runs this session recorded, each with
// how long it lasted and its samples, the database, and the command that
// shows one (which works as printed); with --no-record, that nothing was kept.
TEST(ConsoleTui, OnExitTheSessionsRunsAreNamedWithTheCommandThatShowsThem) {
  if (!have_tmux()) GTEST_SKIP() << "tmux is not installed: the TUI test needs it (apt-get install tmux)";
  test::TempDir dir;
  const std::string db = dir.file("runs.db");
  std::string s;
  {
    Tmux t = console_in("--sim hasel --db " + shell_quote(db), 160, 48);
    ASSERT_TRUE(t.started()) << t.error();
    ASSERT_TRUE(t.wait_until_connected(s)) << s;
    t.keys(shell_quote(":run 1s") + " Enter");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "run 1: ") && !contains(x, "RUNNING"); }, s))
        << s;
    t.keys("F5");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "run 2 RUNNING"); }, s)) << s;
    t.keys("F6");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "stopped:"); }, s)) << s;
    t.keys("q");
    ASSERT_TRUE(t.wait_for([](const std::string& x) { return contains(x, "EXIT="); }, s)) << s;
    EXPECT_EQ(quit_status(s), "EXIT=0") << s;
  }  // one tmux server at a time

  RunStore store(db);
  EXPECT_TRUE(contains(s, "nlsoft-console: 2 runs recorded this session in " + db)) << s;
  for (int id : {1, 2}) {
    const std::string row = line_with(s, "  run " + std::to_string(id) + "  ");
    EXPECT_TRUE(contains(row, " s  " + std::to_string(store.run(id).samples) + " samples")) << s;
  }
  const std::string see = "nlsoft-console runs show 2 --db " + db;
  ASSERT_TRUE(contains(s, "see one: " + see)) << s;
  const auto shown = run_process(std::string(NLSOFT_CONSOLE_BIN) + see.substr(std::string("nlsoft-console").size()));
  EXPECT_EQ(shown.code, 0) << shown.output;
  EXPECT_TRUE(contains(shown.output, std::to_string(store.run(2).samples) + " samples")) << shown.output;

  Tmux u = console_in("--sim hasel --no-record", 80, 24);
  ASSERT_TRUE(u.started()) << u.error();
  ASSERT_TRUE(u.wait_for(panel_read, s)) << s;
  u.keys(shell_quote(":run 300ms") + " Enter");
  ASSERT_TRUE(u.wait_for([](const std::string& x) { return contains(x, "run 1: ") && !contains(x, "RUNNING"); }, s))
      << s;
  u.keys("q");
  ASSERT_TRUE(u.wait_for([](const std::string& x) { return contains(x, "EXIT="); }, s)) << s;
  EXPECT_TRUE(contains(s, "nlsoft-console: 1 run this session, not kept (--no-record)")) << s;
}

}  // namespace
}  // namespace nlsoft::console
