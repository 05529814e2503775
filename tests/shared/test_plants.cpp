// Simulated plants: msd against its closed-form solution; the soft-actuator
// surrogates for determinism, their task-space box, lag, hysteresis, sensors
// and the reference fits their headers promise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <cstring>

#include "shared/plant_hasel.hpp"
#include "shared/plant_msd.hpp"
#include "shared/plant_tendon.hpp"
#include "shared/platform_id.hpp"
#include "shared/reference.hpp"
#include "shared/rng.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft {
namespace {

// Test arithmetic runs in double; plant constants and outputs are float.
double D(float v) { return static_cast<double>(v); }

// ---------------------------------------------------------------- msd

// x(t) from rest under constant u: underdamped step response of
// x'' + 2 zeta w0 x' + w0^2 x = u.
double msd_step_response(double u, double t) {
  const double w0 = 20.0, zeta = 0.125;
  const double wd = w0 * std::sqrt(1.0 - zeta * zeta);
  const double xs = u / (w0 * w0);
  return xs * (1.0 - std::exp(-zeta * w0 * t) *
                         (std::cos(wd * t) + zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * t)));
}

TEST(MsdPlant, ConstantsAreThePapers) {
  EXPECT_FLOAT_EQ(MsdPlant::kStiffness, 40.0f);
  EXPECT_FLOAT_EQ(MsdPlant::kDamping, 0.5f);
  EXPECT_FLOAT_EQ(MsdPlant::kMass, 0.1f);
  EXPECT_EQ(MsdPlant::m, 1);
  EXPECT_EQ(MsdPlant::n, 1);
  EXPECT_EQ(MsdPlant::w, 0);
}

TEST(MsdPlant, StepResponseMatchesClosedForm) {
  for (double u : {40.0, 200.0, 800.0}) {  // steady 0.1, 0.5 and 2 m
    MsdPlant p;
    p.reset(0);
    const float uf = static_cast<float>(u);
    double worst = 0.0;
    for (int k = 1; k <= 5000; ++k) {  // 5 s at 1 kHz
      p.step(&uf, MsdPlant::kDt);
      float y;
      p.output(&y);
      worst = std::fmax(worst, std::fabs(static_cast<double>(y) - msd_step_response(u, k * 1e-3)));
    }
    EXPECT_LT(worst, 1e-5) << "u = " << u;
  }
}

TEST(MsdPlant, FreeResponseMatchesClosedForm) {
  MsdPlant p;
  p.set_state(0.3f, 0.0f);
  const float zero = 0.0f;
  const double w0 = 20.0, zeta = 0.125, wd = w0 * std::sqrt(1.0 - zeta * zeta);
  for (int k = 1; k <= 2000; ++k) {
    p.step(&zero, 1e-3f);
    const double t = k * 1e-3;
    const double x = 0.3 * std::exp(-zeta * w0 * t) *
                     (std::cos(wd * t) + zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * t));
    ASSERT_NEAR(p.position(), x, 1e-5) << k;
  }
}

TEST(MsdPlant, LongerControlPeriodGivesTheSameTrajectory) {
  MsdPlant a, b;
  a.reset(0);
  b.reset(0);
  for (int k = 0; k < 1000; ++k) {
    const float u = MsdPlant::training_input(static_cast<float>(k) * 4e-3f);
    a.step(&u, 4e-3f);
    for (int i = 0; i < 4; ++i) b.step(&u, 1e-3f);
  }
  EXPECT_NEAR(a.position(), b.position(), 1e-5);
}

TEST(MsdPlant, TrainingInputAndClamping) {
  for (float t : {0.0f, 0.3f, 1.0f, 17.5f}) {
    EXPECT_NEAR(MsdPlant::training_input(t), 500.0 * std::sin(2.0 * D(t)), 1e-3);
  }
  MsdPlant a, b;
  a.reset(0);
  b.reset(0);
  const float huge = 1e9f, lim = MsdPlant::kUMax, nan = NAN, zero = 0.0f;
  a.step(&huge, 1e-3f);
  b.step(&lim, 1e-3f);
  EXPECT_EQ(a.position(), b.position());
  a.step(&nan, 1e-3f);
  b.step(&zero, 1e-3f);
  EXPECT_EQ(a.position(), b.position());
  const float before = a.position();
  a.step(&lim, NAN);
  a.step(&lim, -1.0f);
  EXPECT_EQ(a.position(), before);
  float umin, umax;
  MsdPlant::input_limits(&umin, &umax);
  EXPECT_FLOAT_EQ(umin, -2000.0f);
  EXPECT_FLOAT_EQ(umax, 2000.0f);
}

TEST(MsdPlant, ResonantBangBangStaysInsideItsBound) {
  MsdPlant p;
  p.reset(0);
  float lo, hi;
  MsdPlant::output_box(&lo, &hi);
  float peak = 0.0f;
  for (int k = 0; k < 20000; ++k) {
    const float u = p.velocity() >= 0.0f ? MsdPlant::kUMax : -MsdPlant::kUMax;
    p.step(&u, 1e-3f);
    peak = std::fmax(peak, std::fabs(p.position()));
  }
  EXPECT_GT(peak, 20.0f);  // the bound is tight, not a loose guess
  EXPECT_LT(peak, hi);
  EXPECT_GT(-peak, lo);
}

// ------------------------------------------------- soft plants (typed)

template <class P>
class SoftPlant : public ::testing::Test {};
using SoftPlants = ::testing::Types<HaselPlant, TendonPlant>;
TYPED_TEST_SUITE(SoftPlant, SoftPlants);

template <class P>
void random_input(Rng& r, float* u) {
  float lo[P::m], hi[P::m];
  P::input_limits(lo, hi);
  for (int i = 0; i < P::m; ++i) u[i] = r.uniform(lo[i], hi[i]);
}

TYPED_TEST(SoftPlant, DeterministicPerSeed) {
  using P = TypeParam;
  P a, b;
  a.reset(17);
  b.reset(17);
  Rng r(1);
  for (int k = 0; k < 500; ++k) {
    float u[P::m];
    random_input<P>(r, u);
    a.step(u, P::kDt);
    b.step(u, P::kDt);
    float ya[P::n], yb[P::n], la[P::w], lb[P::w];
    a.output(ya);
    b.output(yb);
    a.sensors(la);
    b.sensors(lb);
    ASSERT_EQ(0, std::memcmp(ya, yb, sizeof ya)) << k;
    ASSERT_EQ(0, std::memcmp(la, lb, sizeof la)) << k;
  }
}

TYPED_TEST(SoftPlant, SeedsGiveDifferentNoiseSamePhysics) {
  using P = TypeParam;
  P a, b;
  a.reset(1);
  b.reset(2);
  Rng r(3);
  int differing = 0;
  for (int k = 0; k < 100; ++k) {
    float u[P::m];
    random_input<P>(r, u);
    a.step(u, P::kDt);
    b.step(u, P::kDt);
    float ya[P::n], yb[P::n], la[P::w], lb[P::w];
    a.output(ya);
    b.output(yb);
    for (int i = 0; i < P::n; ++i) ASSERT_EQ(ya[i], yb[i]);
    a.sensors(la);
    b.sensors(lb);
    for (int j = 0; j < P::w; ++j) differing += la[j] != lb[j] ? 1 : 0;
  }
  EXPECT_GT(differing, 100 * P::w * 9 / 10);
}

TYPED_TEST(SoftPlant, StaysInTheTaskSpaceBoxForAnyInputs) {
  using P = TypeParam;
  float lo[P::n], hi[P::n], umin[P::m], umax[P::m];
  P::output_box(lo, hi);
  P::input_limits(umin, umax);
  float seen_lo[P::n], seen_hi[P::n];
  for (int i = 0; i < P::n; ++i) {
    seen_lo[i] = 1e9f;
    seen_hi[i] = -1e9f;
  }
  P p;
  p.reset(4);
  Rng r(8);
  float u[P::m];
  for (int k = 0; k < 40000; ++k) {
    const int mode = (k / 300) % 4;  // random, bang-bang, held extremes, hostile
    if (mode == 0 || k % 40 == 0) {
      for (int i = 0; i < P::m; ++i) {
        switch (mode) {
          case 0: u[i] = r.uniform(umin[i], umax[i]); break;
          case 1:
          case 2: u[i] = r.uniform() < 0.5f ? umin[i] : umax[i]; break;
          default: {
            const float hostile[] = {NAN, INFINITY, -INFINITY, 1e30f, -1e30f, 0.0f};
            u[i] = hostile[static_cast<int>(r.uniform() * 6.0f) % 6];
          }
        }
      }
    }
    p.step(u, P::kDt);
    float y[P::n], l[P::w];
    p.output(y);
    p.sensors(l);
    for (int i = 0; i < P::n; ++i) {
      ASSERT_TRUE(std::isfinite(y[i]));
      ASSERT_GE(y[i], lo[i]) << "axis " << i << " step " << k;
      ASSERT_LE(y[i], hi[i]) << "axis " << i << " step " << k;
      seen_lo[i] = std::fmin(seen_lo[i], y[i]);
      seen_hi[i] = std::fmax(seen_hi[i], y[i]);
    }
    for (int j = 0; j < P::w; ++j) ASSERT_TRUE(std::isfinite(l[j]));
  }
  // ...and the motion fills a good part of the box on every axis.
  for (int i = 0; i < P::n; ++i) EXPECT_GT(seen_hi[i] - seen_lo[i], 0.6f * (hi[i] - lo[i])) << i;
}

TYPED_TEST(SoftPlant, UnusableDtDoesNotAdvance) {
  using P = TypeParam;
  P p;
  p.reset(0);
  float umax[P::m], umin[P::m], y0[P::n], y1[P::n];
  P::input_limits(umin, umax);
  p.output(y0);
  p.step(umax, NAN);
  p.step(umax, -1.0f);
  p.step(umax, 0.0f);
  p.output(y1);
  for (int i = 0; i < P::n; ++i) EXPECT_EQ(y0[i], y1[i]);
}

TYPED_TEST(SoftPlant, SensorsTrackTheStateAboveTheNoise) {
  using P = TypeParam;
  auto mean_sensors = [](P& p, float* mean) {
    for (int j = 0; j < P::w; ++j) mean[j] = 0.0f;
    for (int s = 0; s < 50; ++s) {
      float l[P::w];
      p.sensors(l);
      for (int j = 0; j < P::w; ++j) mean[j] += l[j] / 50.0f;
    }
  };
  P p;
  p.reset(5);
  float umin[P::m], umax[P::m], neutral[P::m], u[P::m];
  P::input_limits(umin, umax);
  P::neutral_input(neutral);
  float at_neutral[P::w];
  mean_sensors(p, at_neutral);
  for (int i = 0; i < P::m; ++i) u[i] = neutral[i] + 0.6f * (umax[i] - neutral[i]);
  u[0] = neutral[0];  // not a pure common mode
  for (int k = 0; k < 200; ++k) p.step(u, P::kDt);
  float moved[P::w];
  mean_sensors(p, moved);
  float change = 0.0f;
  for (int j = 0; j < P::w; ++j) change = std::fmax(change, std::fabs(moved[j] - at_neutral[j]));
  EXPECT_GT(change, 20.0f * P::kNoise);

  // Noise level as documented, on channels away from the [0, 1] clip.
  double sum = 0.0, sum2 = 0.0;
  int count = 0;
  for (int s = 0; s < 4000; ++s) {
    float l[P::w];
    p.sensors(l);
    for (int j = 0; j < P::w; ++j) {
      if (moved[j] < 0.1f || (P::w == 11 && moved[j] > 0.9f)) continue;
      const double d = static_cast<double>(l[j] - moved[j]);
      sum += d;
      sum2 += d * d;
      ++count;
    }
  }
  ASSERT_GT(count, 1000);
  const double sigma = std::sqrt(sum2 / count - (sum / count) * (sum / count));
  EXPECT_NEAR(sigma, static_cast<double>(P::kNoise), 0.2 * static_cast<double>(P::kNoise));
}

// ---------------------------------------------------------------- hasel

TEST(HaselPlant, NeutralIsTheCentreOfTheBox) {
  HaselPlant p;
  p.reset(0);
  float u[6], y[3], lo[3], hi[3];
  HaselPlant::neutral_input(u);
  for (int k = 0; k < 100; ++k) p.step(u, HaselPlant::kDt);
  p.output(y);
  HaselPlant::output_box(lo, hi);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(y[i], 0.5f * (lo[i] + hi[i]), 1e-3f) << i;
  EXPECT_NEAR(hi[0] - lo[0], 23.0f, 1e-4f);
  EXPECT_NEAR(hi[1] - lo[1], 20.2f, 1e-4f);
  EXPECT_NEAR(hi[2] - lo[2], 19.2f, 1e-4f);
}

TEST(HaselPlant, FirstOrderLagWithItsTimeConstants) {
  HaselPlant p;
  p.reset(0);
  float u[6], y[3];
  for (float& v : u) v = 0.8f;  // common mode: pure z, no tilt
  p.output(y);
  const double z0 = y[2];
  const double s = (0.8 - 2.0 * D(HaselPlant::kPlay)) / (1.0 - 2.0 * D(HaselPlant::kPlay));
  const double z_end =
      D(HaselPlant::kZ0) + D(HaselPlant::kStroke) * D(HaselPlant::statics(static_cast<float>(s)));
  double prev = z0;
  for (int k = 1; k <= 60; ++k) {
    p.step(u, HaselPlant::kDt);
    p.output(y);
    const double expect = z_end + (z0 - z_end) * std::exp(-k * (1.0 / 130.0) / 0.025);
    ASSERT_NEAR(y[2], expect, 2e-4) << k;
    ASSERT_GE(y[2], prev);
    prev = y[2];
  }
  // Falling back is slower (draining): 45 ms.
  for (float& v : u) v = 0.5f;
  p.output(y);
  const double top = y[2];
  p.step(u, HaselPlant::kDt);
  p.output(y);
  const double target = HaselPlant::kZ0 + HaselPlant::kStroke * HaselPlant::statics(
                                              (0.5f + HaselPlant::kPlay - HaselPlant::kPlay) /
                                              (1.0f - 2.0f * HaselPlant::kPlay));
  const double fraction = (static_cast<double>(y[2]) - target) / (top - target);
  EXPECT_NEAR(fraction, std::exp(-(1.0 / 130.0) / 0.045), 1e-4);
}

TEST(HaselPlant, HysteresisUpSweepDiffersFromDownSweep) {
  auto sweep_to_half = [](float from) {
    HaselPlant p;
    p.reset(0);
    float u[6];
    for (int k = 0; k <= 600; ++k) {  // slow ramp from `from` to 0.5
      const float v = from + (0.5f - from) * static_cast<float>(k) / 600.0f;
      for (float& x : u) x = v;
      p.step(u, HaselPlant::kDt);
    }
    for (int k = 0; k < 300; ++k) p.step(u, HaselPlant::kDt);  // settle: lag gone
    float y[3];
    p.output(y);
    return y[2];
  };
  const float up = sweep_to_half(0.2f);
  const float down = sweep_to_half(0.8f);
  // Rate independent memory: the play half-width h = 0.03 of the drive.
  EXPECT_GT(down - up, 1.0f);
  EXPECT_LT(down - up, 3.0f);
}

TEST(HaselPlant, TiltMovesTheEndEffectorSideways) {
  HaselPlant p;
  p.reset(0);
  float u[6] = {0.9f, 0.7f, 0.3f, 0.1f, 0.3f, 0.7f};  // raise the phi = 0 side
  for (int k = 0; k < 200; ++k) p.step(u, HaselPlant::kDt);
  float y[3];
  p.output(y);
  EXPECT_GT(y[0], 3.0f);
  EXPECT_NEAR(y[1], 0.0f, 1e-3f);
  const float v[6] = {0.5f, 0.9f, 0.9f, 0.5f, 0.1f, 0.1f};  // phi = 90 deg side
  for (int k = 0; k < 200; ++k) p.step(v, HaselPlant::kDt);
  p.output(y);
  EXPECT_GT(y[1], 3.0f);
}

// Drives the plant to a steady pose with extensions e (inverting the statics
// and approaching each play state from the neutral side).
void hold_extensions(HaselPlant& p, const double e[6]) {
  const double h = D(HaselPlant::kPlay);
  float u[6];
  for (int i = 0; i < 6; ++i) {
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      (D(HaselPlant::statics(static_cast<float>(mid))) < e[i] ? lo : hi) = mid;
    }
    const double play_state = h + lo * (1.0 - 2.0 * h);
    u[i] = static_cast<float>(play_state > 0.5 ? play_state + h : play_state - h);
  }
  p.reset(0);
  for (int k = 0; k < 400; ++k) p.step(u, HaselPlant::kDt);
}

TEST(HaselPlant, SwirlAtTheDocumentedScaleAndCentreIsReachable) {
  RefParams ref{};
  ref.kind = RefKind::Swirl;
  ref.hold = 1;
  ref.scale = HaselPlant::kSwirlScale;
  for (int i = 0; i < 3; ++i) ref.c[i] = HaselPlant::kSwirlCentre[i];
  const double H = D(HaselPlant::kHeight), K = D(HaselPlant::kKappa);
  const double c6[6] = {1, 0.5, -0.5, -1, -0.5, 0.5};
  const double s6[6] = {0, 0.8660254037844386, 0.8660254037844386, 0, -0.8660254037844386,
                        -0.8660254037844386};
  double min_margin = 1.0;
  for (uint32_t k = 0; k < swirl::kPoints; k += 7) {
    float target[3];
    reference_at(ref, nullptr, k, target, 3);
    // Invert the platform geometry to the plate's mean height and slopes...
    const double ax = std::asin(D(target[0]) / H);
    const double ay = std::asin(D(target[1]) / (H * std::cos(ax)));
    const double tx = ax / K, ty = ay / K;
    const double mean =
        (D(target[2]) - D(HaselPlant::kZ0) + H * (1.0 - std::cos(ax) * std::cos(ay))) /
        D(HaselPlant::kStroke);
    // ...then find extensions inside [0.1, 0.9] with those three moments by
    // alternating projections (box, affine set).
    double e[6] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
    for (int it = 0; it < 3000; ++it) {
      for (double& v : e) v = std::fmin(0.9, std::fmax(0.1, v));
      double r0 = -6.0 * mean, r1 = -3.0 * tx, r2 = -3.0 * ty;
      for (int i = 0; i < 6; ++i) {
        r0 += e[i];
        r1 += e[i] * c6[i];
        r2 += e[i] * s6[i];
      }
      for (int i = 0; i < 6; ++i) e[i] -= r0 / 6.0 + r1 * c6[i] / 3.0 + r2 * s6[i] / 3.0;
    }
    for (double v : e) min_margin = std::fmin(min_margin, std::fmin(v, 1.0 - v));
    HaselPlant p;
    hold_extensions(p, e);
    float y[3];
    p.output(y);
    for (int i = 0; i < 3; ++i) ASSERT_NEAR(y[i], target[i], 2e-3) << "point " << k << " axis " << i;
  }
  EXPECT_GT(min_margin, 0.09);  // every actuator stays ~10 % away from its ends
}

// ---------------------------------------------------------------- tendon

TEST(TendonPlant, NeutralAndBox) {
  TendonPlant p;
  p.reset(0);
  float y[3], lo[3], hi[3];
  p.output(y);
  for (float v : y) EXPECT_NEAR(v, 0.0f, 1e-6f);
  TendonPlant::output_box(lo, hi);
  EXPECT_NEAR(hi[0] - lo[0], 40.4f, 1e-4f);
  EXPECT_NEAR(hi[1] - lo[1], 28.3f, 1e-4f);
  EXPECT_NEAR(hi[2] - lo[2], 35.0f, 1e-4f);
}

TEST(TendonPlant, ServoLagThenMonotoneBend) {
  TendonPlant p;
  p.reset(0);
  const float u[2] = {0.6f, 0.0f};
  const double dt = 1.0 / 120.0;
  float prev = 0.0f;
  float y_final[3];
  for (int k = 1; k <= 120; ++k) {
    p.step(u, TendonPlant::kDt);
    ASSERT_NEAR(p.servo_angle(0), 0.6 * (1.0 - std::exp(-k * dt / 0.05)), 1e-5) << k;
    float y[3];
    p.output(y);
    ASSERT_GE(y[1], prev);  // no overshoot, no reversal
    prev = y[1];
    if (k == 120) std::memcpy(y_final, y, sizeof y);
  }
  // 63 % of the final motion after roughly one servo time constant (6 steps),
  // a little later because of the slack and the stiffening.
  TendonPlant q;
  q.reset(0);
  int k63 = 0;
  for (int k = 1; k <= 120 && k63 == 0; ++k) {
    q.step(u, TendonPlant::kDt);
    float y[3];
    q.output(y);
    if (y[1] >= 0.632f * y_final[1]) k63 = k;
  }
  EXPECT_GE(k63, 4);
  EXPECT_LE(k63, 12);
  // Depth follows the bowl: bending either way pulls the tip back.
  EXPECT_GT(y_final[0], 1.0f);
}

TEST(TendonPlant, SlackSwallowsSmallCommands) {
  TendonPlant p;
  p.reset(0);
  float u[2] = {0.9f * TendonPlant::kSlack, -0.9f * TendonPlant::kSlack};
  for (int k = 0; k < 200; ++k) p.step(u, TendonPlant::kDt);
  float y[3];
  p.output(y);
  for (float v : y) EXPECT_EQ(v, 0.0f);  // tendons still slack
  u[0] = 1.5f * TendonPlant::kSlack;
  for (int k = 0; k < 200; ++k) p.step(u, TendonPlant::kDt);
  p.output(y);
  EXPECT_GT(y[1], 0.1f);
}

TEST(TendonPlant, SlackHysteresis) {
  auto approach_zero_from = [](float from) {
    TendonPlant p;
    p.reset(0);
    float u[2] = {from, 0.0f};
    for (int k = 0; k < 200; ++k) p.step(u, TendonPlant::kDt);
    u[0] = 0.0f;
    for (int k = 0; k < 200; ++k) p.step(u, TendonPlant::kDt);
    float y[3];
    p.output(y);
    return y[1];
  };
  const float from_left = approach_zero_from(-0.8f);
  const float from_right = approach_zero_from(0.8f);
  EXPECT_GT(from_right - from_left, 1.0f);  // 2 b of play, about 1.7 mm
  EXPECT_LT(from_right - from_left, 2.5f);
}

TEST(TendonPlant, InfinityIsApproximatelyReachable) {
  RefParams ref{};
  ref.kind = RefKind::Infinity;
  ref.A = TendonPlant::kInfinity[0];
  ref.B = TendonPlant::kInfinity[1];
  ref.C = TendonPlant::kInfinity[2];
  for (int i = 0; i < 3; ++i) ref.c[i] = TendonPlant::kCentre[i];
  ref.omega = 2.0f * 3.14159265f / 240.0f;
  const double amax = TendonPlant::kBendMax * std::tanh((TendonPlant::kUMax - TendonPlant::kSlack) /
                                                        TendonPlant::kBendSoft);
  for (uint32_t k = 0; k < 240; k += 5) {
    float target[3];
    reference_at(ref, nullptr, k, target, 3);
    // Invert the kinematics for the bend angles (fixed point on the sag).
    double a0 = 0.0, a1 = 0.0;
    for (int it = 0; it < 100; ++it) {
      a1 = std::asin((D(target[2]) + D(TendonPlant::kSag) * (1.0 - std::cos(a0))) / D(TendonPlant::kRho2));
      a0 = std::asin(D(target[1]) / (D(TendonPlant::kRho1) * std::cos(0.35 * a1)));
    }
    ASSERT_LT(std::fabs(a0), 0.9 * amax) << k;
    ASSERT_LT(std::fabs(a1), 0.9 * amax) << k;
    // Hold the servo commands that give those bends (slack taken up from 0).
    float u[2];
    const double a[2] = {a0, a1};
    for (int i = 0; i < 2; ++i) {
      const double q = D(TendonPlant::kBendSoft) * std::atanh(a[i] / D(TendonPlant::kBendMax));
      u[i] = static_cast<float>(q + (q >= 0.0 ? 1.0 : -1.0) * D(TendonPlant::kSlack));
    }
    TendonPlant p;
    p.reset(0);
    for (int s = 0; s < 300; ++s) p.step(u, TendonPlant::kDt);
    float y[3];
    p.output(y);
    EXPECT_NEAR(y[1], target[1], 2e-3) << k;
    EXPECT_NEAR(y[2], target[2], 2e-3) << k;
    EXPECT_NEAR(y[0], target[0], 6.5) << k;  // depth lives on the bowl
  }
}

// ---------------------------------------------------------------- SimPlant

TEST(SimPlant, DimensionsAndPeriods) {
  SimPlant s;
  ASSERT_TRUE(s.select(PlantKind::Msd));
  EXPECT_EQ(s.m(), 1);
  EXPECT_EQ(s.n(), 1);
  EXPECT_EQ(s.w(), 0);
  EXPECT_FLOAT_EQ(s.dt(), 1e-3f);
  ASSERT_TRUE(s.select(PlantKind::Hasel));
  EXPECT_EQ(s.m(), 6);
  EXPECT_EQ(s.n(), 3);
  EXPECT_EQ(s.w(), 18);
  EXPECT_FLOAT_EQ(s.dt(), 1.0f / 130.0f);
  ASSERT_TRUE(s.select(PlantKind::Tendon));
  EXPECT_EQ(s.m(), 2);
  EXPECT_EQ(s.n(), 3);
  EXPECT_EQ(s.w(), 11);
  EXPECT_FLOAT_EQ(s.dt(), 1.0f / 120.0f);
}

// A kind no registry row carries, and the generic plant without its spec,
// are refused and change nothing: no plant stands in for another.
TEST(SimPlant, RefusesAKindItCannotRun) {
  SimPlant s;
  ASSERT_TRUE(s.select(PlantKind::Tendon));
  EXPECT_FALSE(s.select(static_cast<PlantKind>(9)));
  EXPECT_EQ(s.kind(), PlantKind::Tendon);
  EXPECT_FALSE(s.select(PlantKind::Generic));
  EXPECT_EQ(s.kind(), PlantKind::Tendon);
  EXPECT_EQ(s.m(), 2);
}

// The registry is the one list: each row's name finds it, its dimensions
// and period are its plant's, and no other name finds a plant.
TEST(PlantRegistry, EachRowIsItsPlant) {
  for (const PlantEntry& e : kPlantRegistry) {
    ASSERT_EQ(find_plant(e.name), &e) << e.name;
    ASSERT_EQ(plant_entry(e.kind), &e) << e.name;
    SimPlant s;
    if (e.kind == PlantKind::Generic) continue;
    ASSERT_TRUE(s.select(e.kind)) << e.name;
    EXPECT_EQ(s.m(), e.m) << e.name;
    EXPECT_EQ(s.n(), e.n) << e.name;
    EXPECT_EQ(s.w(), e.w) << e.name;
    EXPECT_EQ(s.dt(), e.period) << e.name;
  }
  EXPECT_EQ(find_plant("has"), nullptr);
  EXPECT_EQ(find_plant("haselx"), nullptr);
  EXPECT_EQ(find_plant(""), nullptr);
  EXPECT_EQ(find_plant(nullptr), nullptr);
  EXPECT_EQ(plant_entry(static_cast<PlantKind>(kPlantCount)), nullptr);
}

template <class P>
void expect_same_as_direct(PlantKind kind) {
  SimPlant s;
  ASSERT_TRUE(s.select(kind, 21));
  P p;
  p.reset(21);
  Rng r(2);
  float umin[kMaxPlantM], umax[kMaxPlantM];
  s.input_limits(umin, umax);
  for (int k = 0; k < 300; ++k) {
    float u[kMaxPlantM];
    for (int i = 0; i < s.m(); ++i) u[i] = r.uniform(umin[i], umax[i]);
    s.step(u, s.dt());
    p.step(u, P::kDt);
    float ys[kMaxPlantN], yp[kMaxPlantN], ls[kMaxPlantW], lp[kMaxPlantW];
    s.output(ys);
    p.output(yp);
    s.sensors(ls);
    p.sensors(lp);
    for (int i = 0; i < P::n; ++i) ASSERT_EQ(ys[i], yp[i]);
    for (int j = 0; j < P::w; ++j) ASSERT_EQ(ls[j], lp[j]);
  }
}

TEST(SimPlant, ForwardsToTheSelectedPlant) {
  expect_same_as_direct<MsdPlant>(PlantKind::Msd);
  expect_same_as_direct<HaselPlant>(PlantKind::Hasel);
  expect_same_as_direct<TendonPlant>(PlantKind::Tendon);
}

}  // namespace
}  // namespace nlsoft
