// Tracking and step-response metrics against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>

#include "app/metrics/tracking_metrics.hpp"

using namespace nlsoft;
using namespace nlsoft::console;

TEST(Metrics, RmseAndNormalisedRmse) {
  // two axes, four rows; axis 0 off by 1 everywhere, axis 1 exact
  const std::vector<float> ref = {0, 0, 2, 10, 4, 20, 6, 30};
  const std::vector<float> y = {1, 0, 3, 10, 5, 20, 7, 30};
  const TrackingMetrics m = tracking_metrics(ref, y, 2);
  EXPECT_DOUBLE_EQ(m.rmse[0], 1.0);
  EXPECT_DOUBLE_EQ(m.rmse[1], 0.0);
  EXPECT_DOUBLE_EQ(m.nrmse, 1.0 / 30.0);  // max RMSE / max range (axis 1: 30)
  EXPECT_DOUBLE_EQ(m.max_error, 1.0);
  // weighting axis 0 out of the tracked set
  const float Q[2] = {1e-4f, 1.0f};
  const TrackingMetrics w = tracking_metrics(ref, y, 2, Q);
  EXPECT_DOUBLE_EQ(w.nrmse, 0.0);
  EXPECT_DOUBLE_EQ(w.nrmse_all, 1.0 / 30.0);
}

TEST(Metrics, StepResponseRiseOvershootAndSteadyError) {
  RefParams r{};
  r.kind = RefKind::Step;
  r.level_count = 1;
  r.levels[0] = 1.0f;
  r.hold = 100;
  // first-order-ish response with a 10 % bump, settling at 0.99
  std::vector<float> y(100);
  for (int k = 0; k < 100; ++k) y[size_t(k)] = k < 13 ? 0.07f * float(k + 1) : (k < 30 ? 1.1f : 0.99f);
  const auto s = step_responses(r, y, 1, 0, 0.01f);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_NEAR(s[0].rise_s, 0.13, 1e-6);  // 0.07 (k+1) >= 0.9 first at k = 12: 13 rows
  EXPECT_NEAR(s[0].overshoot_pct, 10.0, 1e-4);
  EXPECT_NEAR(s[0].steady_error, 0.01, 1e-6);
}

TEST(Metrics, Percentile) {
  std::vector<float> v;
  for (int i = 1; i <= 100; ++i) v.push_back(float(i));
  EXPECT_DOUBLE_EQ(percentile(v, 0.5), 51.0);
  EXPECT_DOUBLE_EQ(percentile(v, 0.99), 99.0);
  EXPECT_DOUBLE_EQ(percentile({}, 0.5), 0.0);
}

TEST(Metrics, FlatReferenceHasNoNormalisedError) {
  // nothing to normalise by: NaN, never a perfect-looking 0
  const std::vector<float> ref = {1, 1, 1};
  const std::vector<float> y = {1.5f, 0.5f, 1.0f};
  const TrackingMetrics m = tracking_metrics(ref, y, 1);
  EXPECT_GT(m.rmse[0], 0.0);
  EXPECT_TRUE(std::isnan(m.nrmse));
  EXPECT_FALSE(m.nrmse < 0.05);
}

// The one computation of u_effort and u_saturated (runs, tune, simulate),
// with each actuator's share of steps at a limit.
TEST(Metrics, InputEffortAndTheShareOfStepsEachInputSpendsAtALimit) {
  // two inputs over [0, 10] and [-1, 1], four rows: u0 pinned at its upper
  // limit throughout, u1 at its lower limit once (within 1 % of the range).
  const std::vector<float> u = {10, 0, 10, -0.99f, 10, 0.5f, 9.95f, 0};
  const InputMetrics m = input_metrics(u, 2, {0, -1}, {10, 1});
  ASSERT_EQ(m.saturated_per_input.size(), 2u);
  EXPECT_DOUBLE_EQ(m.saturated_per_input[0], 1.0);
  EXPECT_DOUBLE_EQ(m.saturated_per_input[1], 0.25);
  EXPECT_DOUBLE_EQ(m.u_saturated, 5.0 / 8.0);
  // steps: u0 0, 0, -0.005 of its range; u1 -0.495, 0.745, -0.25
  const double sq = 0.005 * 0.005 + 0.495 * 0.495 + 0.745 * 0.745 + 0.25 * 0.25;
  EXPECT_NEAR(m.u_effort, std::sqrt(sq / 6.0), 1e-6);
  // Without limits: effort in raw units, no saturation figures.
  const InputMetrics raw = input_metrics(u, 2, {}, {});
  EXPECT_TRUE(std::isnan(raw.u_saturated));
  EXPECT_TRUE(raw.saturated_per_input.empty());
  EXPECT_GT(raw.u_effort, 0.0);
}
