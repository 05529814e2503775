// The PID baseline: each term against its definition, the anti-windup, the
// closed loop on the msd plant with the paper's gains, and finite outputs
// under hostile inputs.
#include <gtest/gtest.h>

#include <cmath>

#include "shared/pid.hpp"
#include "shared/plant_msd.hpp"
#include "shared/reference.hpp"

namespace nlsoft {
namespace {

// The paper's gains and the output scale that gives its response: rigs/msd.toml's
// [pid] (tests/host/rig checks the file holds them).
constexpr PidGains kMsdPidGains{1.93f, 4.01f, 5.99f};
constexpr float kMsdPidOutputScale = 60.0f;

Pid make(const PidGains& g, float lo, float hi, float scale = 1.0f, float tau = 0.0f,
         int axes = 1) {
  float umin[kPidMaxAxes], umax[kPidMaxAxes];
  for (int i = 0; i < kPidMaxAxes; ++i) {
    umin[i] = lo;
    umax[i] = hi;
  }
  Pid pid;
  EXPECT_TRUE(pid.configure(axes, g, umin, umax, scale, tau));
  return pid;
}

TEST(Pid, ConfigureRejectsBadValuesAndKeepsTheOldOnes) {
  Pid pid = make({2.0f, 0.0f, 0.0f}, -10.0f, 10.0f);
  const float lo[2] = {-1.0f, -1.0f}, hi[2] = {1.0f, 1.0f}, bad_hi[2] = {1.0f, -2.0f};
  EXPECT_FALSE(pid.configure(0, kMsdPidGains, lo, hi));
  EXPECT_FALSE(pid.configure(kPidMaxAxes + 1, kMsdPidGains, lo, hi));
  EXPECT_FALSE(pid.configure(1, {NAN, 0.0f, 0.0f}, lo, hi));
  EXPECT_FALSE(pid.configure(1, {1.0f, -1.0f, 0.0f}, lo, hi));
  EXPECT_FALSE(pid.configure(1, kMsdPidGains, lo, hi, 0.0f));
  EXPECT_FALSE(pid.configure(1, kMsdPidGains, lo, hi, INFINITY));
  EXPECT_FALSE(pid.configure(1, kMsdPidGains, lo, hi, 1.0f, -0.1f));
  EXPECT_FALSE(pid.configure(2, kMsdPidGains, lo, bad_hi));
  EXPECT_FALSE(pid.configure(1, kMsdPidGains, nullptr, hi));
  EXPECT_EQ(pid.axes(), 1);
  EXPECT_FLOAT_EQ(pid.gains().kp, 2.0f);
  const float r = 3.0f, y = 1.0f;
  float u;
  pid.step(&r, &y, 0.01f, &u);
  EXPECT_FLOAT_EQ(u, 4.0f);  // still Kp = 2, limits +-10
}

TEST(Pid, ProportionalTermAndClamp) {
  Pid pid = make({2.0f, 0.0f, 0.0f}, -3.0f, 3.0f, 0.5f);
  const float r = 2.0f;
  float y = 0.5f, u;
  pid.step(&r, &y, 0.01f, &u);
  EXPECT_FLOAT_EQ(u, 0.5f * 2.0f * 1.5f);
  y = -10.0f;
  pid.step(&r, &y, 0.01f, &u);
  EXPECT_FLOAT_EQ(u, 3.0f);
  y = 20.0f;
  pid.step(&r, &y, 0.01f, &u);
  EXPECT_FLOAT_EQ(u, -3.0f);
}

TEST(Pid, IntegralAccumulatesErrorTimesDt) {
  Pid pid = make({0.0f, 2.0f, 0.0f}, -100.0f, 100.0f);
  const float r = 1.0f, y = 0.0f;
  float u = 0.0f;
  for (int k = 1; k <= 10; ++k) {
    pid.step(&r, &y, 0.1f, &u);
    EXPECT_NEAR(u, 2.0f * 0.1f * static_cast<float>(k), 1e-5f) << k;
  }
}

TEST(Pid, DerivativeOnMeasurementHasNoSetpointKick) {
  Pid pid = make({0.0f, 0.0f, 3.0f}, -100.0f, 100.0f);
  float r = 0.0f, y = 1.0f, u;
  pid.step(&r, &y, 0.1f, &u);
  EXPECT_FLOAT_EQ(u, 0.0f);  // no history yet
  r = 50.0f;                 // setpoint jump
  pid.step(&r, &y, 0.1f, &u);
  EXPECT_FLOAT_EQ(u, 0.0f);
  y = 1.5f;  // measurement rising at 5 /s
  pid.step(&r, &y, 0.1f, &u);
  EXPECT_NEAR(u, -15.0f, 1e-4f);
}

TEST(Pid, DerivativeFilterSmoothsAndConverges) {
  Pid raw = make({0.0f, 0.0f, 1.0f}, -100.0f, 100.0f);
  Pid filtered = make({0.0f, 0.0f, 1.0f}, -100.0f, 100.0f, 1.0f, 0.05f);
  const float r = 0.0f;
  float ur = 0.0f, uf = 0.0f;
  for (int k = 0; k < 200; ++k) {
    const float y = 0.01f * static_cast<float>(k);  // ramp, slope 1 /s at dt 0.01
    raw.step(&r, &y, 0.01f, &ur);
    filtered.step(&r, &y, 0.01f, &uf);
    if (k == 1) {
      EXPECT_LT(std::fabs(uf), 0.5f * std::fabs(ur));
    }
  }
  EXPECT_NEAR(ur, -1.0f, 1e-3f);
  EXPECT_NEAR(uf, -1.0f, 1e-3f);
}

TEST(Pid, AntiWindupKeepsTheIntegratorBoundedAndRecoversFast) {
  Pid pid = make({1.0f, 10.0f, 0.0f}, -1.0f, 1.0f);
  float r = 100.0f, y = 0.0f, u;
  for (int k = 0; k < 1000; ++k) pid.step(&r, &y, 0.01f, &u);  // 10 s pinned high
  EXPECT_FLOAT_EQ(u, 1.0f);
  EXPECT_LT(std::fabs(pid.integral(0)), 1.1f);  // a windup would reach ~10^4
  r = 0.0f;
  y = 0.5f;  // now the output must come down
  int steps = 0;
  do {
    pid.step(&r, &y, 0.01f, &u);
    ++steps;
  } while (u > 0.0f && steps < 1000);
  EXPECT_LT(steps, 20);
}

TEST(Pid, AxesAreIndependent) {
  Pid pid = make({1.0f, 0.0f, 0.0f}, -10.0f, 10.0f, 1.0f, 0.0f, 3);
  const float r[3] = {1.0f, 2.0f, 3.0f}, y[3] = {0.0f, NAN, 1.0f};
  float u[3] = {9.0f, 9.0f, 9.0f};
  pid.step(r, y, 0.01f, u);
  EXPECT_FLOAT_EQ(u[0], 1.0f);
  EXPECT_FLOAT_EQ(u[1], 0.0f);  // NaN axis repeats its last (initial) output
  EXPECT_FLOAT_EQ(u[2], 2.0f);
}

// Closed loop on the paper's plant: steps of 0.5, 1 and 2 m (Results).
TEST(Pid, ClosesTheLoopOnMsdWithThePapersGains) {
  const float umin = -MsdPlant::kUMax, umax = MsdPlant::kUMax;
  Pid pid;
  ASSERT_TRUE(pid.configure(1, kMsdPidGains, &umin, &umax, kMsdPidOutputScale));
  MsdPlant plant;
  plant.reset(0);
  RefParams ref{};
  ref.kind = RefKind::Step;
  ref.hold = 20000;  // 20 s per level at 1 kHz
  ref.level_count = 3;
  ref.levels[0] = 0.5f;
  ref.levels[1] = 1.0f;
  ref.levels[2] = 2.0f;
  float peak[3] = {0.0f, 0.0f, 0.0f};
  for (uint32_t k = 0; k < reference_length(ref); ++k) {
    float r, y, u;
    reference_at(ref, nullptr, k, &r, 1);
    plant.output(&y);
    pid.step(&r, &y, MsdPlant::kDt, &u);
    ASSERT_TRUE(std::isfinite(u));
    ASSERT_LE(std::fabs(u), MsdPlant::kUMax);
    plant.step(&u, MsdPlant::kDt);
    const uint32_t seg = k / ref.hold, t = k % ref.hold;
    peak[seg] = std::fmax(peak[seg], plant.position());
    if (t >= 10000) {  // from 10 s into each step: within 3 % of the level
      ASSERT_NEAR(plant.position(), r, 0.03f * r) << "segment " << seg << " t " << t;
    }
    if (t + 1 == ref.hold) {
      EXPECT_NEAR(plant.position(), r, 0.002f * r) << seg;
    }
  }
  for (int s = 0; s < 3; ++s) EXPECT_LT(peak[s], 1.05f * ref.levels[s]) << s;
}

TEST(Pid, StaysFiniteUnderHostileInputs) {
  const float umin = -MsdPlant::kUMax, umax = MsdPlant::kUMax;
  Pid pid;
  ASSERT_TRUE(pid.configure(1, kMsdPidGains, &umin, &umax, kMsdPidOutputScale, 0.01f));
  const float good_r = 1.0f, good_y = 0.2f;
  float u_before;
  pid.step(&good_r, &good_y, 1e-3f, &u_before);
  const float hostile[] = {NAN, INFINITY, -INFINITY, 3e38f, -3e38f};
  for (float h : hostile) {
    float u;
    pid.step(&good_r, &h, 1e-3f, &u);
    ASSERT_TRUE(std::isfinite(u)) << h;
    ASSERT_LE(std::fabs(u), MsdPlant::kUMax);
    pid.step(&h, &good_y, 1e-3f, &u);
    ASSERT_TRUE(std::isfinite(u)) << h;
    pid.step(&good_r, &good_y, h, &u);
    ASSERT_TRUE(std::isfinite(u)) << h;
    pid.step(&good_r, &good_y, 0.0f, &u);
    ASSERT_TRUE(std::isfinite(u));
  }
  float u;
  pid.step(&good_r, &good_y, NAN, &u);
  float u2;
  pid.step(&good_r, &good_y, NAN, &u2);
  EXPECT_EQ(u, u2);  // a bad sample repeats the last output
  // ...and it recovers: back to a normal, finite, clamped output.
  for (int k = 0; k < 100; ++k) pid.step(&good_r, &good_y, 1e-3f, &u);
  EXPECT_TRUE(std::isfinite(u));
  EXPECT_GT(u, 0.0f);
}

}  // namespace
}  // namespace nlsoft
