// LiveConsole in process against nlsoft-firmware-sim: a timed run ends as
// soon as its run is stopped from elsewhere (the TUI quitting, F6), instead
// of polling for telemetry that will never come until its deadline.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "app/live/live_console.hpp"
#include "app/record/run_store.hpp"
#include "temp_dir.hpp"

namespace nlsoft::console {
namespace {

class LiveConsoleRun : public ::testing::Test {
 protected:
  void SetUp() override {
    ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
    LiveOptions o;
    o.sim_platform = "msd";
    o.db_path = dir_.file("runs.db");
    console_ = std::make_unique<LiveConsole>(o);
    console_->connect();
  }
  // Bounded poll: the run starts on another thread.
  bool wait_until_running() {
    for (int i = 0; i < 3000; ++i) {
      if (console_->running() && console_->run_samples() > 0) return true;
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
  auto timed = std::async(std::launch::async, [&] { return console_->run_for(60, "long"); });
  ASSERT_TRUE(wait_until_running());
  const RunSummary stopped = console_->stop_run("stopped at quit");
  ASSERT_EQ(timed.wait_for(std::chrono::seconds(30)), std::future_status::ready)
      << "run_for kept polling after its run was stopped";
  const RunSummary s = timed.get();
  EXPECT_EQ(s.run_id, stopped.run_id);
  EXPECT_EQ(s.end_reason, "stopped at quit");
  EXPECT_FALSE(console_->running());
  RunStore store(dir_.file("runs.db"));
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].end_reason, "stopped at quit") << "the run is closed once, by the stop that won";
}

TEST_F(LiveConsoleRun, RunForEndsWhenCancelledAndKeepsTheRun) {
  std::atomic<bool> cancel{false};
  auto timed = std::async(std::launch::async, [&] { return console_->run_for(60, "long", {}, &cancel); });
  ASSERT_TRUE(wait_until_running());
  cancel = true;
  ASSERT_EQ(timed.wait_for(std::chrono::seconds(30)), std::future_status::ready);
  const RunSummary s = timed.get();
  EXPECT_EQ(s.end_reason, "cancelled");
  EXPECT_GT(s.metrics.samples, 0u);
  EXPECT_FALSE(console_->running());
}

}  // namespace
}  // namespace nlsoft::console
