// Runs in process against nlsoft-firmware-sim (LiveRuns): a timed run ends
// as soon as its run is stopped from elsewhere (the TUI quitting, F6),
// instead of polling for telemetry that will never come until its
// deadline; a run whose firmware goes away or leaves the run ends early and
// says why.
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <future>
#include <regex>
#include <sstream>
#include <thread>

#include "app/link/sim_launcher.hpp"
#include "app/live/live_console.hpp"
#include "app/record/run_store.hpp"
#include "app/script/script_runner.hpp"
#include "app/support/sim_console.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

class LiveConsoleRun : public ::testing::Test {
 protected:
  void SetUp() override { console_ = test_support::connected_sim_console("msd", dir_); }
  // Bounded poll: the run starts on another thread.
  bool wait_until_running() {
    for (int i = 0; i < 3000; ++i) {
      if (console_->runs().running() && console_->runs().samples() > 0) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  test::TempDir dir_;
  std::unique_ptr<LiveConsole> console_;
};

// A 60 s run: were run_for to wait out its deadline (2 x 60 s + 5 s), the
// future below would not be ready within its bound.
TEST_F(LiveConsoleRun, RunForReturnsWhenAnotherThreadStopsTheRun) {
  auto timed = std::async(std::launch::async, [&] { return console_->runs().run_for(60, "long"); });
  ASSERT_TRUE(wait_until_running());
  const RunSummary stopped = console_->runs().stop("stopped at quit");
  ASSERT_EQ(timed.wait_for(std::chrono::seconds(30)), std::future_status::ready)
      << "run_for kept polling after its run was stopped";
  const RunSummary s = timed.get();
  EXPECT_EQ(s.run_id, stopped.run_id);
  EXPECT_EQ(s.end_reason, "stopped at quit");
  EXPECT_FALSE(console_->runs().running());
  RunStore store(dir_.file("runs.db"));
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].end_reason, "stopped at quit") << "the run is closed once, by the stop that won";
}

TEST_F(LiveConsoleRun, RunForEndsWhenCancelledAndKeepsTheRun) {
  std::atomic<bool> cancel{false};
  auto timed = std::async(std::launch::async, [&] { return console_->runs().run_for(60, "long", {}, &cancel); });
  ASSERT_TRUE(wait_until_running());
  cancel = true;
  ASSERT_EQ(timed.wait_for(std::chrono::seconds(30)), std::future_status::ready);
  const RunSummary s = timed.get();
  EXPECT_EQ(s.end_reason, "cancelled");
  EXPECT_GT(s.metrics.samples, 0u);
  EXPECT_FALSE(console_->runs().running());
}

// A run whose firmware goes away, or leaves the run, must not look like a
// run that completed. The simulator is started here, not by the console, so
// the test can end it once the run is under way. The console reaches it
// through a link of the test's own: killed, the simulator's /dev/pts/N is
// free for the next pty anyone opens (another test's firmware, in a
// parallel ctest), and a console still reconnecting by that path would take
// it; the link is removed first, so the reconnects find nothing.
class RunEndingBadly : public ::testing::Test {
 protected:
  void SetUp() override {
    ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
    const std::string pty = sim_.start("msd");
    ASSERT_FALSE(pty.empty());
    port_ = dir_.file("board");
    ASSERT_EQ(::symlink(pty.c_str(), port_.c_str()), 0);
  }
  void kill_firmware() {
    ::unlink(port_.c_str());
    sim_.stop();
  }
  void connect(std::chrono::milliseconds keepalive = std::chrono::milliseconds(300)) {
    LiveOptions o;
    o.port = port_;
    o.db_path = dir_.file("runs.db");
    o.session.keepalive = keepalive;
    console_ = std::make_unique<LiveConsole>(o);
    console_->connect();
  }
  bool wait_until_sampling() {
    for (int i = 0; i < 3000; ++i) {
      if (console_->runs().running() && console_->runs().samples() > 0) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  // Runs `script` while the simulator is killed once the run has samples.
  // The script's exit code, and its output as one text.
  int script_with_firmware_dying(const std::string& text, std::string& out) {
    connect();
    ScriptRunner runner(*console_, [&](const std::string& line) { out += line + "\n"; });
    Script script;
    script.file = "dies.nls";
    int line = 0;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) script.commands.push_back(parse_command(l, script.file, ++line));
    auto rc = std::async(std::launch::async, [&] { return runner.run(script); });
    EXPECT_TRUE(wait_until_sampling());
    kill_firmware();
    EXPECT_EQ(rc.wait_for(std::chrono::seconds(60)), std::future_status::ready);
    return rc.get();
  }

  test::TempDir dir_;
  SimLauncher sim_;
  std::string port_;
  std::unique_ptr<LiveConsole> console_;
};

TEST_F(RunEndingBadly, FirmwareDyingMidRunEndsTheRunEarlyAndRecordsTheOutage) {
  connect();
  auto timed = std::async(std::launch::async, [&] { return console_->runs().run_for(60, "dies"); });
  ASSERT_TRUE(wait_until_sampling());
  kill_firmware();
  ASSERT_EQ(timed.wait_for(std::chrono::seconds(60)), std::future_status::ready)
      << "run_for waited for telemetry from a firmware that is gone";
  const RunSummary s = timed.get();
  EXPECT_TRUE(s.ended_early);
  EXPECT_EQ(s.end_reason.rfind("ended early: telemetry stopped arriving", 0), 0u) << s.end_reason;
  EXPECT_GT(s.metrics.samples, 0u);
  EXPECT_GT(s.metrics.lost_frames, 0u) << "the frames due in the silence it ended in are counted lost";
  EXPECT_GT(s.metrics.wall_s, s.metrics.duration_s) << "the run lasted longer than its samples span";

  RunStore store(dir_.file("runs.db"));
  const auto gaps = store.gaps(s.run_id);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].reason.rfind("run ended early", 0), 0u) << gaps[0].reason;
  EXPECT_GT(gaps[0].duration_s, 0.0) << "the outage is recorded with its duration";
  EXPECT_EQ(gaps[0].after_k + 1, s.metrics.samples) << "the gap follows the last sample";
  EXPECT_EQ(store.run(s.run_id).lost_frames, gaps[0].lost_frames);
}

TEST_F(RunEndingBadly, AScriptWhoseRunEndsEarlyExitsOne) {
  std::string all;
  // lost=ok: the frames lost when the firmware died would fail the expect
  // on their own; here it shows that the commands after the run still run.
  EXPECT_EQ(script_with_firmware_dying("run 60s label=dies\nexpect samples > 0 lost=ok\n", all), 1);
  EXPECT_NE(all.find("dies.nls:1: run 1 did not complete: ended early"), std::string::npos) << all;
  EXPECT_NE(all.find("ok: samples"), std::string::npos) << "later commands still run" << all;
}

TEST_F(RunEndingBadly, EarlyOkTellsTheScriptARunMayEndEarly) {
  std::string all;
  EXPECT_EQ(script_with_firmware_dying("run 60s early=ok\n", all), 0);
  EXPECT_EQ(all.find("did not complete"), std::string::npos) << all;
  EXPECT_NE(all.find("ended early"), std::string::npos) << "the summary still says how the run ended" << all;
}

// The firmware's link watchdog: with the console's keepalive slower than
// watchdog_ms, the firmware puts the actuators in the safe state and stops
// the run's telemetry; STATUS says why, and the run ends early at once.
TEST_F(RunEndingBadly, AWatchdogTripEndsTheRunEarlyAndSaysSo) {
  connect(std::chrono::milliseconds(5000));
  console_->params().set("watchdog_ms", {"100"});
  const RunSummary s = console_->runs().run_for(60, "watchdog");
  EXPECT_TRUE(s.ended_early);
  EXPECT_NE(s.end_reason.find("link watchdog tripped"), std::string::npos) << s.end_reason;
  // The console's own silence beside it: its keepalive every 300 ms is
  // longer than the 100 ms watchdog, so the console is the one to blame.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(s.end_reason, m, std::regex("the console wrote at most ([0-9]+) ms apart during the run")))
      << s.end_reason;
  EXPECT_GE(std::stoi(m[1]), 100) << s.end_reason;
  RunStore store(dir_.file("runs.db"));
  ASSERT_EQ(store.gaps(s.run_id).size(), 1u);
}

// A simulator the host does not schedule for longer than watchdog_ms (a
// loaded machine; here SIGSTOP for 1.5 s) finds the console's keep-alives
// waiting on its port when it runs again: it reads them before its next
// step judges the link, so the run goes on. It used to step first and trip
// the watchdog on its own absence.
TEST_F(RunEndingBadly, ASimulatorPausedPastTheWatchdogDoesNotBlameTheConsole) {
  connect();
  std::atomic<bool> cancel{false};
  auto timed = std::async(std::launch::async, [&] { return console_->runs().run_for(60, "paused", {}, &cancel); });
  ASSERT_TRUE(wait_until_sampling());
  ASSERT_EQ(::kill(sim_.pid(), SIGSTOP), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // watchdog_ms is 1000
  ASSERT_EQ(::kill(sim_.pid(), SIGCONT), 0);
  const uint64_t before = console_->runs().samples();
  for (int i = 0; i < 300 && console_->runs().samples() < before + 100; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_GE(console_->runs().samples(), before + 100) << "the run's telemetry did not resume";
  cancel = true;
  ASSERT_EQ(timed.wait_for(std::chrono::seconds(30)), std::future_status::ready);
  const RunSummary s = timed.get();
  EXPECT_FALSE(s.ended_early) << s.end_reason;
  EXPECT_EQ(s.end_reason, "cancelled");
}

// A hold asked for by the user pauses telemetry on purpose: that is not the
// firmware going away.
TEST_F(RunEndingBadly, AUserHoldIsNotTakenForAnOutage) {
  connect();
  std::atomic<bool> cancel{false};
  auto timed = std::async(std::launch::async, [&] { return console_->runs().run_for(60, "held", {}, &cancel); });
  ASSERT_TRUE(wait_until_sampling());
  console_->runs().hold(protocol::HoldMode::Hold);
  // Longer than the silence limit (3 s) and than a STATUS period (1 s).
  std::this_thread::sleep_for(std::chrono::seconds(5));
  EXPECT_EQ(timed.wait_for(std::chrono::seconds(0)), std::future_status::timeout) << "the held run was ended";
  console_->runs().hold(protocol::HoldMode::Resume);
  cancel = true;
  ASSERT_EQ(timed.wait_for(std::chrono::seconds(30)), std::future_status::ready);
  const RunSummary s = timed.get();
  EXPECT_FALSE(s.ended_early) << s.end_reason;
  EXPECT_EQ(s.end_reason, "cancelled");
}

}  // namespace
}  // namespace nlsoft::console
