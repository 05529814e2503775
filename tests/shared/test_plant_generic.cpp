// The generic plant (shared/plant_generic.hpp): limits and guarantees, seeds,
// the static map at steady state, hysteresis widths, lags, sensors, and
// SimPlant holding it.
#include <gtest/gtest.h>

#include <cmath>

#include "shared/plant_generic.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft {
namespace {

// Three inputs of different shapes and ranges, two outputs, five sensors.
constexpr GenericPlantSpec three_by_two() {
  GenericPlantSpec s;
  s.m = 3, s.n = 2, s.w = 5;
  s.dt = 1.0f / 80.0f;
  s.input[0] = {0.0f, 1.0f, 0.5f, 10.0f, GenericShape::Tanh, 0.3f, 1.0f, 0.0f, 0.05f};
  s.input[1] = {-2.0f, 2.0f, 0.0f, 3.0f, GenericShape::Power, 1.0f, 2.0f, 0.0f, 0.08f};
  s.input[2] = {0.0f, 10.0f, 2.0f, 1.0f, GenericShape::Saturation, 5.0f, 1.0f, 0.0f, 0.0f};
  s.output[0] = {-20.0f, 20.0f, 1.0f, 0.03f};
  s.output[1] = {-5.0f, 15.0f, 4.0f, 0.0f};
  const float B[2][3] = {{1.0f, 0.5f, 0.2f}, {-0.4f, 1.0f, 0.3f}};
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) s.B[j][i] = B[j][i];
  for (int k = 0; k < 5; ++k) {
    s.sensor[k] = {0.1f * float(k), 0.01f};
    s.C[k][k] = 1.0f;  // sensors 0..2 read the actuators, 3..4 the outputs
  }
  return s;
}

TEST(GenericPlant, DimensionsLimitsAndRestComeFromTheSpec) {
  const GenericPlantSpec spec = three_by_two();
  GenericPlant p(spec, 3);
  EXPECT_EQ(p.m(), 3);
  EXPECT_EQ(p.n(), 2);
  EXPECT_EQ(p.w(), 5);
  EXPECT_FLOAT_EQ(p.dt(), 1.0f / 80.0f);
  float lo[3], hi[3], neutral[3], blo[2], bhi[2], y[2];
  p.input_limits(lo, hi);
  p.neutral_input(neutral);
  p.output_box(blo, bhi);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(lo[i], spec.input[i].min);
    EXPECT_EQ(hi[i], spec.input[i].max);
    EXPECT_EQ(neutral[i], spec.input[i].neutral);
  }
  p.output(y);
  EXPECT_EQ(y[0], 1.0f);  // at rest: the output offsets
  EXPECT_EQ(y[1], 4.0f);
  EXPECT_EQ(blo[1], -5.0f);
  EXPECT_EQ(bhi[1], 15.0f);
}

TEST(GenericPlant, OutputsStayInTheBoxAndFiniteWhateverTheInput) {
  GenericPlantSpec spec = three_by_two();
  spec.input[0].gain = 1e6f;  // drives y0 into its box at once
  GenericPlant p(spec, 1);
  Rng r(4);
  const float bad[] = {NAN, INFINITY, -INFINITY, 1e30f, -1e30f};
  for (int k = 0; k < 2000; ++k) {
    float u[3];
    for (int i = 0; i < 3; ++i)
      u[i] = k % 7 == 0 ? bad[(k / 7 + i) % 5] : r.uniform(spec.input[i].min - 3.0f, spec.input[i].max + 3.0f);
    const float dts[] = {spec.dt, NAN, -1.0f, 100.0f, 0.0f};
    p.step(u, k % 11 == 0 ? dts[(k / 11) % 5] : spec.dt);
    float y[2], l[5];
    p.output(y);
    p.sensors(l);
    for (int j = 0; j < 2; ++j) {
      ASSERT_TRUE(std::isfinite(y[j]));
      ASSERT_GE(y[j], spec.output[j].lo);
      ASSERT_LE(y[j], spec.output[j].hi);
    }
    for (float v : l) ASSERT_TRUE(std::isfinite(v));
  }
}

TEST(GenericPlant, NonFiniteInputActsAsNeutralAndBadDtDoesNotAdvance) {
  const GenericPlantSpec spec = three_by_two();
  GenericPlant a(spec, 2), b(spec, 2);
  float away[3] = {0.9f, 1.5f, 8.0f};
  for (int k = 0; k < 40; ++k) a.step(away, spec.dt), b.step(away, spec.dt);
  const float nan_u[3] = {NAN, INFINITY, -INFINITY};
  float neutral[3];
  b.neutral_input(neutral);
  for (int k = 0; k < 40; ++k) a.step(nan_u, spec.dt), b.step(neutral, spec.dt);
  float ya[2], yb[2];
  a.output(ya);
  b.output(yb);
  EXPECT_EQ(ya[0], yb[0]);
  EXPECT_EQ(ya[1], yb[1]);
  a.step(away, NAN);
  a.step(away, -0.5f);
  a.step(away, 0.0f);
  a.output(yb);
  EXPECT_EQ(ya[0], yb[0]);
  EXPECT_EQ(ya[1], yb[1]);
}

TEST(GenericPlant, OneSeedOneRunBitForBit) {
  const GenericPlantSpec spec = three_by_two();
  auto run = [&](uint32_t seed, float* out) {
    GenericPlant p(spec, seed);
    Rng r(9);
    for (int k = 0; k < 500; ++k) {
      float u[3];
      for (int i = 0; i < 3; ++i) u[i] = r.uniform(spec.input[i].min, spec.input[i].max);
      p.step(u, spec.dt);
      p.sensors(out + 7 * k);
      p.output(out + 7 * k + 5);
    }
  };
  static float first[3500], again[3500], other[3500];
  run(7, first);
  run(7, again);
  run(8, other);
  int differ = 0;
  for (int i = 0; i < 3500; ++i) {
    ASSERT_EQ(first[i], again[i]) << i;
    differ += first[i] != other[i];
  }
  EXPECT_GT(differ, 2000);  // another seed: other sensor noise
  // ... and reset(seed) on a used plant starts the same run again.
  GenericPlant p(spec, 1);
  float u[3] = {0.7f, 1.0f, 3.0f};
  for (int k = 0; k < 50; ++k) p.step(u, spec.dt);
  p.reset(7);
  GenericPlant q(spec, 7);
  float lp[5], lq[5];
  p.sensors(lp);
  q.sensors(lq);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(lp[k], lq[k]);
}

// A HIL image's plant: the spec a constexpr (its generated nlsoft_rig.hpp),
// the dimensions constants as the named plants have them.
constexpr GenericPlantSpec kFixedSpec = three_by_two();
using FixedPlant = FixedGenericPlant<kFixedSpec>;
static_assert(FixedPlant::m == 3 && FixedPlant::n == 2 && FixedPlant::w == 5, "the spec's dimensions");
static_assert(generic_spec_problem(kFixedSpec) == nullptr, "checked at compile time");

TEST(GenericPlant, AFixedSpecStepsBitForBitAsTheConfiguredPlant) {
  EXPECT_EQ(FixedPlant::kDt, kFixedSpec.dt);
  float umin[3], umax[3], neutral[3], lo[2], hi[2];
  FixedPlant::input_limits(umin, umax);
  FixedPlant::neutral_input(neutral);
  FixedPlant::output_box(lo, hi);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(umin[i], kFixedSpec.input[i].min);
    EXPECT_EQ(umax[i], kFixedSpec.input[i].max);
    EXPECT_EQ(neutral[i], kFixedSpec.input[i].neutral);
  }
  EXPECT_EQ(lo[1], -5.0f);
  EXPECT_EQ(hi[1], 15.0f);
  // The same seed and inputs, NaN and a bad dt among them: the same sensors
  // and outputs to the bit.
  GenericPlant configured(kFixedSpec, 4);
  FixedPlant fixed;
  fixed.reset(4);
  Rng r(3);
  int moved = 0;
  for (int k = 0; k < 400; ++k) {
    float u[3];
    for (int i = 0; i < 3; ++i) u[i] = r.uniform(kFixedSpec.input[i].min - 1.0f, kFixedSpec.input[i].max + 1.0f);
    if (k % 97 == 5) u[1] = NAN;
    const float dt = k % 131 == 7 ? -1.0f : kFixedSpec.dt;
    configured.step(u, dt);
    fixed.step(u, dt);
    float la[5], lb[5], ya[2], yb[2];
    configured.sensors(la);
    fixed.sensors(lb);
    configured.output(ya);
    fixed.output(yb);
    for (int c = 0; c < 5; ++c) ASSERT_EQ(la[c], lb[c]) << k;
    for (int j = 0; j < 2; ++j) ASSERT_EQ(ya[j], yb[j]) << k;
    moved += ya[0] != 1.0f;
  }
  EXPECT_GT(moved, 300);
}

TEST(GenericPlant, SteadyStateIsTheStaticMap) {
  const GenericPlantSpec spec = three_by_two();
  Rng r(5);
  for (int trial = 0; trial < 20; ++trial) {
    GenericPlant p(spec, 0);
    float u[3];
    for (int i = 0; i < 3; ++i) u[i] = r.uniform(spec.input[i].min, spec.input[i].max);
    for (int k = 0; k < 400; ++k) p.step(u, spec.dt);  // 5 s, 60 of the slowest lag
    float y[2], want[2];
    p.output(y);
    p.static_output(u, want);
    // The map by hand: offset + B (gain * shape(u - neutral)).
    const float d0 = u[0] - 0.5f, d1 = u[1], d2 = u[2] - 2.0f;
    const float a[3] = {10.0f * 0.3f * std::tanh(d0 / 0.3f), 3.0f * std::copysign(d1 * d1, d1),
                        std::fmax(-5.0f, std::fmin(5.0f, d2))};
    for (int j = 0; j < 2; ++j) {
      float t = spec.output[j].offset;
      for (int i = 0; i < 3; ++i) t += spec.B[j][i] * a[i];
      t = std::fmax(spec.output[j].lo, std::fmin(spec.output[j].hi, t));
      EXPECT_NEAR(want[j], t, 1e-4f) << trial;
      EXPECT_NEAR(y[j], t, 1e-4f) << trial;
    }
  }
}

TEST(GenericPlant, PlayMakesRisingAndFallingSweepsDifferByTwiceItsWidth) {
  // One linear input, gain 2, play 0.1: the output lags the input by 0.1
  // each way, so a slow sweep up and down differs by 2 * 0.1 * 2 = 0.4.
  GenericPlantSpec s;
  s.m = 1, s.n = 1, s.w = 0;
  s.dt = 0.01f;
  s.input[0] = {-1.0f, 1.0f, 0.0f, 2.0f, GenericShape::Linear, 1.0f, 1.0f, 0.1f, 0.0f};
  s.output[0] = {-10.0f, 10.0f, 0.0f, 0.0f};
  s.B[0][0] = 1.0f;
  GenericPlant p(s, 0);
  auto at = [&](float u) {
    p.step(&u, s.dt);
    float y;
    p.output(&y);
    return y;
  };
  for (int k = 0; k <= 80; ++k) at(-0.01f * float(k));  // down to -0.8
  float rising = 0, falling = 0;
  for (int k = -80; k <= 80; ++k) {
    const float y = at(0.01f * float(k));
    if (k == 30) rising = y;
  }
  for (int k = 80; k >= -80; --k) {
    const float y = at(0.01f * float(k));
    if (k == 30) falling = y;
  }
  EXPECT_NEAR(rising, 2.0f * (0.3f - 0.1f), 1e-5f);
  EXPECT_NEAR(falling, 2.0f * (0.3f + 0.1f), 1e-5f);
  EXPECT_NEAR(falling - rising, 0.4f, 1e-5f);
  // Inside the dead band a reversal moves nothing.
  const float held = at(0.25f);
  EXPECT_EQ(at(0.25f - 0.15f), held);
  EXPECT_NE(at(0.25f - 0.25f), held);
}

TEST(GenericPlant, LagsReachTheirTimeConstantsShare) {
  // One input lagged by 0.1 s, no output lag: after 0.1 s of a step the
  // output has covered 1 - 1/e of it, exactly as shared/plant.hpp's lag.
  GenericPlantSpec s;
  s.m = 1, s.n = 1;
  s.dt = 0.01f;
  s.input[0] = {0.0f, 1.0f, 0.0f, 1.0f, GenericShape::Linear, 1.0f, 1.0f, 0.0f, 0.1f};
  s.output[0] = {-1.0f, 2.0f, 0.0f, 0.0f};
  s.B[0][0] = 1.0f;
  GenericPlant p(s, 0);
  const float u = 1.0f;
  for (int k = 0; k < 10; ++k) p.step(&u, s.dt);
  float y;
  p.output(&y);
  EXPECT_NEAR(y, 1.0f - std::exp(-1.0f), 1e-5f);
  // The same lag on the output instead, the input instantaneous.
  s.input[0].tau = 0.0f;
  s.output[0].tau = 0.1f;
  GenericPlant q(s, 0);
  for (int k = 0; k < 10; ++k) q.step(&u, s.dt);
  q.output(&y);
  EXPECT_NEAR(y, 1.0f - std::exp(-1.0f), 1e-5f);
}

TEST(GenericPlant, SensorsAreTheMapOfTheStatePlusOffsetAndNoise) {
  GenericPlantSpec spec = three_by_two();
  for (int k = 0; k < 5; ++k) spec.sensor[k].noise = 0.0f;
  spec.C[4][0] = 2.0f;  // sensor 4 also reads actuator 0
  GenericPlant p(spec, 0);
  const float u[3] = {0.8f, -1.0f, 6.0f};
  for (int k = 0; k < 30; ++k) p.step(u, spec.dt);
  float l[5], y[2];
  p.sensors(l);
  p.output(y);
  for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(l[i], 0.1f * float(i) + p.actuator(i));
  EXPECT_FLOAT_EQ(l[3], 0.3f + y[0]);
  EXPECT_FLOAT_EQ(l[4], 0.4f + y[1] + 2.0f * p.actuator(0));
  // Noise of sigma 0.05 on a constant state: the spread is the sigma.
  spec.sensor[3].noise = 0.05f;
  GenericPlant q(spec, 11);
  for (int k = 0; k < 30; ++k) q.step(u, spec.dt);
  double sum = 0, sq = 0;
  const int count = 20000;
  for (int k = 0; k < count; ++k) {
    q.sensors(l);
    sum += double(l[3]);
    sq += double(l[3]) * double(l[3]);
  }
  const double mean = sum / count, sd = std::sqrt(sq / count - mean * mean);
  EXPECT_NEAR(mean, 0.3 + double(y[0]), 2e-3);
  EXPECT_NEAR(sd, 0.05, 2e-3);
}

TEST(GenericPlant, RefusesASpecItCannotRunAndKeepsThePreviousOne) {
  const GenericPlantSpec good = three_by_two();
  EXPECT_EQ(generic_spec_problem(good), nullptr);
  GenericPlant p(good, 0);
  auto refused = [&](GenericPlantSpec s, const char* why) {
    const char* problem = generic_spec_problem(s);
    ASSERT_NE(problem, nullptr) << why;
    EXPECT_FALSE(p.configure(s)) << why;
    EXPECT_EQ(p.m(), 3) << why;
  };
  GenericPlantSpec s = good;
  s.input[1].tau = -0.1f;
  refused(s, "negative input time constant");
  s = good;
  s.output[0].tau = -1.0f;
  refused(s, "negative output time constant");
  s = good;
  s.B[1][2] = NAN;
  refused(s, "NaN coupling");
  s = good;
  s.C[4][4] = INFINITY;
  refused(s, "infinite sensor map");
  s = good;
  s.input[0].neutral = 2.0f;
  refused(s, "neutral outside the limits");
  s = good;
  s.output[1].lo = 20.0f;
  refused(s, "empty box");
  s = good;
  s.m = 9;
  refused(s, "m over capacity");
  s = good;
  s.dt = 0.0f;
  refused(s, "no period");
  s = good;
  s.input[2].knee = 0.0f;
  refused(s, "zero knee");
}

constexpr GenericPlantSpec kEmbedded = [] {
  GenericPlantSpec s{};
  s.m = 2, s.n = 1, s.w = 1;
  s.dt = 0.01f;
  s.input[0] = {0.0f, 1.0f, 0.0f, 1.0f, GenericShape::Tanh, 0.5f, 1.0f, 0.02f, 0.05f};
  s.input[1] = {0.0f, 1.0f, 0.0f, 1.0f, GenericShape::Linear, 1.0f, 1.0f, 0.0f, 0.05f};
  s.output[0] = {-2.0f, 2.0f, 0.0f, 0.0f};
  s.B[0][0] = 1.0f;
  s.B[0][1] = -1.0f;
  s.C[0][2] = 1.0f;
  return s;
}();

TEST(SimPlant, HoldsAGenericPlantBesideTheNamedOnes) {
  SimPlant s;
  ASSERT_TRUE(s.select(PlantKind::Hasel, 3));
  EXPECT_FALSE(s.is_generic());
  const GenericPlantSpec spec = three_by_two();
  ASSERT_TRUE(s.select(spec, 21));
  EXPECT_TRUE(s.is_generic());
  EXPECT_EQ(s.m(), 3);
  EXPECT_EQ(s.n(), 2);
  EXPECT_EQ(s.w(), 5);
  EXPECT_FLOAT_EQ(s.dt(), 1.0f / 80.0f);
  GenericPlant direct(spec, 21);
  Rng r(2);
  for (int k = 0; k < 300; ++k) {
    float u[3];
    for (int i = 0; i < 3; ++i) u[i] = r.uniform(spec.input[i].min, spec.input[i].max);
    s.step(u, s.dt());
    direct.step(u, spec.dt);
    float ys[kMaxPlantN], yd[2], ls[kMaxPlantW], ld[5];
    s.output(ys);
    direct.output(yd);
    s.sensors(ls);
    direct.sensors(ld);
    for (int j = 0; j < 2; ++j) ASSERT_EQ(ys[j], yd[j]);
    for (int j = 0; j < 5; ++j) ASSERT_EQ(ls[j], ld[j]);
  }
  // A refused spec changes nothing; a named plant selects back.
  GenericPlantSpec bad = spec;
  bad.input[0].tau = -1.0f;
  EXPECT_FALSE(s.select(bad));
  EXPECT_EQ(s.m(), 3);
  ASSERT_TRUE(s.select(PlantKind::Tendon));
  EXPECT_FALSE(s.is_generic());
  EXPECT_EQ(s.m(), 2);
  EXPECT_EQ(s.w(), 11);
  // A constexpr spec, as a firmware image embeds it.
  static_assert(kEmbedded.m == 2 && kEmbedded.n == 1, "constexpr spec");
  ASSERT_TRUE(s.select(kEmbedded));
  EXPECT_EQ(s.n(), 1);
}

}  // namespace
}  // namespace nlsoft
