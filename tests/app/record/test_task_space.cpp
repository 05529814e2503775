// nrmse_space: tracking error over the rig's task space, defined where the
// reference's own range is not (a hold) and the same yardstick for every
// reference on a rig.
#include <gtest/gtest.h>

#include <cmath>

#include "app/record/run_metrics.hpp"
#include "app/record/task_space.hpp"

namespace nlsoft::console {
namespace {

// A hasel run holding (1, 2, 3) mm while the plant sits 0.46 mm off in y0.
RunSeries hold_with_offset() {
  RunSeries s;
  s.n = 3;
  s.m = 0;
  s.has_y_ref = s.has_y_true = s.has_y_hat = true;
  for (uint32_t k = 0; k < 100; ++k) {
    s.step.push_back(k);
    s.time_us.push_back(k * 7692);
    for (float v : {1.0f, 2.0f, 3.0f}) s.y_ref.push_back(v), s.y_hat.push_back(v);
    for (float v : {1.46f, 2.0f, 3.0f}) s.y_true.push_back(v);
  }
  return s;
}

TEST(TaskSpace, NrmseSpaceIsDefinedForAHoldWhereNrmseIsNot) {
  RunRow run;
  run.platform = "hasel";
  run.loop_rate_hz = 130;
  const RunMetrics m = run_metrics(run, hold_with_offset(), {}, 0);
  EXPECT_FALSE(std::isfinite(m.truth.nrmse)) << "a flat reference has no range to divide by";
  ASSERT_TRUE(std::isfinite(m.nrmse_space));
  EXPECT_NEAR(m.nrmse_space, 0.46 / 23.0, 1e-6);
  EXPECT_NEAR(*metric_value(m, "nrmse_space"), 0.02, 1e-6);
}

TEST(TaskSpace, UnknownRigsHaveNone) {
  EXPECT_EQ(task_space("tendon"), (std::vector<double>{40.4, 28.3, 35.0}));
  EXPECT_TRUE(task_space("custom").empty());
  RunRow run;
  run.platform = "custom";
  EXPECT_TRUE(std::isnan(run_metrics(run, hold_with_offset(), {}, 0).nrmse_space));
}

}  // namespace
}  // namespace nlsoft::console
