// What the live console does with samples and LOG lines a firmware should
// not send: a step count that goes back is no progress (a run read it as
// "completed" after 52 of 600 samples), a LOG flood is bounded with a count
// of what was left out, and a run without samples has no error of 0.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "app/live/log_limiter.hpp"
#include "app/live/sample_intake.hpp"
#include "app/record/recorder.hpp"
#include "app/record/run_metrics.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

namespace p = nlsoft::protocol;

TEST(SampleIntake, AStepCountThatGoesBackIsNotProgressAndEndsTheRun) {
  test::TempDir dir;
  Recorder recorder(dir.file("r.db"));
  ActiveRun run(recorder);
  SampleIntake intake(run, nullptr);
  run.id = 1;
  p::Telemetry t;
  t.mask = p::telemetry_field::kStep;
  t.n = 1;
  t.m = 1;
  for (uint32_t step : {1000u, 1001u, 1002u, 3u, 4u}) {
    t.step = step;
    intake.on_telemetry(t, 0);
  }
  EXPECT_TRUE(run.step_went_back.load());
  EXPECT_EQ(run.step_back_from.load(), 1002u);
  EXPECT_EQ(run.step_back_to.load(), 3u);
  EXPECT_EQ(run.k.load(), 3u) << "the steps before the last one are not recorded";
  EXPECT_EQ(run.last_step.load(), 1002u) << "progress never reads an unsigned difference that wrapped";
  EXPECT_EQ(run.lost.load(), 2u);
  run.id = 0;
}

TEST(LogLimiter, AFloodIsBoundedAndTheDroppedAreCounted) {
  LogLimiter limiter;
  const auto t0 = std::chrono::steady_clock::now();
  std::string words;
  int shown = 0;
  for (int i = 0; i < 10000; ++i) shown += limiter.admit(t0, words) ? 1 : 0;
  EXPECT_EQ(shown, int(LogLimiter::kBurst));
  EXPECT_EQ(limiter.dropped_total(), 10000u - uint64_t(LogLimiter::kBurst));
  // A second on, lines pass again, the first of them with the count.
  EXPECT_TRUE(limiter.admit(t0 + std::chrono::seconds(1), words));
  EXPECT_EQ(words, "9950 firmware LOG lines not shown (more than 20 a second)");
  EXPECT_TRUE(limiter.admit(t0 + std::chrono::seconds(1), words));
  EXPECT_EQ(words, "") << "said once";
}

TEST(RunMetrics, ARunWithoutSamplesHasNoTrackingErrorRatherThanZero) {
  RunMetrics m;
  m.has_true = true;
  EXPECT_FALSE(metric_value(m, "max_error").has_value());
  EXPECT_FALSE(metric_value(m, "rmse").has_value());
  EXPECT_EQ(metric_value(m, "samples"), 0.0);
  m.truth.rmse = {0.25};
  m.truth.max_error = 0.5;
  EXPECT_EQ(metric_value(m, "max_error"), 0.5);
}

}  // namespace
}  // namespace nlsoft::console
