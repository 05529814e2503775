// The TUI's worker thread: a task that throws must not end the program
// (std::terminate with the terminal still in raw mode), and stop() must
// leave no thread touching what the tasks use.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "app/tui/worker.hpp"

namespace nlsoft::console::tui {
namespace {

TEST(ConsoleWorker, AnEscapingExceptionIsReportedAndTheNextTaskStillRuns) {
  std::mutex mu;
  std::vector<std::string> reports;
  std::promise<void> after;
  {
    Worker w([&](const std::string& s) {
      std::lock_guard<std::mutex> lock(mu);
      reports.push_back(s);
    });
    w.post("reading parameters", [] { throw std::runtime_error("no reply to PARAM_GET"); });
    w.post("exporting", [] { throw 42; });
    w.post("next", [&] { after.set_value(); });
    ASSERT_EQ(after.get_future().wait_for(std::chrono::seconds(30)), std::future_status::ready)
        << "the worker thread did not survive a throwing task";
  }
  ASSERT_EQ(reports.size(), 2u);
  EXPECT_EQ(reports[0], "reading parameters: no reply to PARAM_GET");
  EXPECT_EQ(reports[1], "exporting: unknown error");
}

TEST(ConsoleWorker, WithoutAReportCallbackAnEscapingExceptionGoesToStderr) {
  std::promise<void> after;
  testing::internal::CaptureStderr();
  {
    Worker w;
    w.post("loading", [] { throw std::logic_error("boom"); });
    w.post("next", [&] { after.set_value(); });
    ASSERT_EQ(after.get_future().wait_for(std::chrono::seconds(30)), std::future_status::ready);
  }
  EXPECT_NE(testing::internal::GetCapturedStderr().find("loading: boom"), std::string::npos);
}

TEST(ConsoleWorker, StopFinishesTheRunningTaskDropsTheQueueAndJoins) {
  std::atomic<bool> release{false}, later_ran{false};
  std::promise<void> started;
  Worker w;
  w.post("long", [&] {
    started.set_value();
    while (!release.load()) std::this_thread::yield();
  });
  w.post("queued", [&] { later_ran = true; });
  ASSERT_EQ(started.get_future().wait_for(std::chrono::seconds(30)), std::future_status::ready);
  EXPECT_EQ(w.busy(), "long (+1 queued)");
  auto stopping = std::async(std::launch::async, [&] { w.stop(); });
  // Released only once stop() has emptied the queue, so the queued task
  // cannot slip in between.
  for (int i = 0; i < 3000 && w.busy() != "long"; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(w.busy(), "long");
  release = true;
  ASSERT_EQ(stopping.wait_for(std::chrono::seconds(30)), std::future_status::ready);
  EXPECT_FALSE(later_ran.load()) << "a task queued behind the running one ran after stop()";
  w.post("after stop", [&] { later_ran = true; });  // ignored, not run on a dead thread
  w.stop();
  EXPECT_FALSE(later_ran.load());
}

}  // namespace
}  // namespace nlsoft::console::tui
