// References against their formulas in docs/platforms.md, evaluated independently in
// double precision here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>

#include "shared/reference.hpp"
#include "shared/remainder.hpp"
#include "shared/rng.hpp"

namespace nlsoft {
namespace {

constexpr double kPi = 3.14159265358979323846;

RefParams base(RefKind kind) {
  RefParams p{};
  p.kind = kind;
  p.A = 3.0f;
  p.B = 5.0f;
  p.C = 7.0f;
  p.c[0] = 1.0f;
  p.c[1] = -2.0f;
  p.c[2] = 0.5f;
  p.omega = 0.013f;
  p.lambda = 400.0f;
  p.scale = 1.0f;
  p.hold = 10;
  return p;
}

void eval(const RefParams& p, uint32_t k, float y[3], const ReferenceTable* t = nullptr) {
  reference_at(p, t, k, y, 3);
}

TEST(Reference, InfinityMatchesFormula) {
  const RefParams p = base(RefKind::Infinity);
  for (uint32_t k : {0u, 1u, 17u, 121u, 250u, 1000u, 12345u}) {
    const double a = static_cast<double>(p.omega) * k;
    float y[3];
    eval(p, k, y);
    EXPECT_NEAR(y[0], 3.0 * std::sin(a) * std::sin(a) + 1.0, 1e-4) << k;
    EXPECT_NEAR(y[1], 5.0 * std::sin(a) * std::cos(a) - 2.0, 1e-4) << k;
    EXPECT_NEAR(y[2], 7.0 * std::sin(a) + 0.5, 1e-4) << k;
  }
  EXPECT_EQ(reference_length(p), 0u);
}

// docs/rig-file.md: an Infinity on two outputs (its first two components) is
// an ellipse A wide along y0 and B along y1, not a figure eight: every point
// lies on ((y0 - c0 - A/2) / (A/2))^2 + ((y1 - c1) / (B/2))^2 = 1 (the
// eight is the path's y1-y2 plane).
TEST(Reference, InfinityOnTwoOutputsIsAnEllipse) {
  const RefParams p = base(RefKind::Infinity);
  for (uint32_t k = 0; k < 600; k += 7) {
    float y[2];
    reference_at(p, nullptr, k, y, 2);
    const double a = double(p.A) / 2.0, b = double(p.B) / 2.0;
    const double u = (double(y[0]) - double(p.c[0]) - a) / a, v = (double(y[1]) - double(p.c[1])) / b;
    EXPECT_NEAR(u * u + v * v, 1.0, 1e-3) << "k = " << k;
  }
}

TEST(Reference, PringleMatchesFormula) {
  const RefParams p = base(RefKind::Pringle);
  for (uint32_t k : {0u, 1u, 100u, 200u, 333u, 400u, 401u, 99999u}) {
    const double phi = 2.0 * kPi * k / 400.0;
    const double y1 = 5.0 * std::cos(phi) - 2.0;
    const double y2 = 7.0 * std::sin(phi) + 0.5;
    const double y0 = 3.0 * ((y2 - 0.5) * (y2 - 0.5) / 25.0 - (y1 + 2.0) * (y1 + 2.0) / 49.0) + 1.0;
    float y[3];
    eval(p, k, y);
    EXPECT_NEAR(y[0], y0, 1e-4) << k;
    EXPECT_NEAR(y[1], y1, 1e-4) << k;
    EXPECT_NEAR(y[2], y2, 1e-4) << k;
  }
  float a[3], b[3];
  eval(p, 37, a);
  eval(p, 37 + 400 * 50, b);  // periodic in lambda, at full precision
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], 1e-5);
}

TEST(Reference, DiagonalMatchesFormula) {
  const RefParams p = base(RefKind::Diagonal);
  for (uint32_t k : {0u, 1u, 100u, 777u, 2000u, 5000u}) {
    const double phi = 2.0 * kPi * k / 400.0 + 1e-6 * k * static_cast<double>(k);
    const double y1 = 5.0 * std::sin(phi) - 2.0;
    const double y2 = 7.0 * std::sin(phi) + 0.5;
    const double y0 = 3.0 * ((y2 - 0.5) * (y2 - 0.5) / 25.0 - (y1 + 2.0) * (y1 + 2.0) / 49.0) + 1.0;
    float y[3];
    eval(p, k, y);
    EXPECT_NEAR(y[0], y0, 2e-4) << k;
    EXPECT_NEAR(y[1], y1, 2e-4) << k;
    EXPECT_NEAR(y[2], y2, 2e-4) << k;
  }
}

TEST(Reference, SwirlSegmentBoundaries) {
  RefParams p = base(RefKind::Swirl);
  p.scale = 2.0f;
  const uint32_t h = p.hold;
  const double th_max = 4.0 * kPi;
  struct Case {
    uint32_t k;
    double x, y, z;  // unscaled point
  } cases[] = {
      {0, 0, 0, 0},
      {30 * h - 1, 0, 0, 0},
      {30 * h, 0, 0, 0},                         // rise starts at z = 0
      {31 * h, 0, 0, 0.5 / 99.0},
      {130 * h - 1, 0, 0, 0.5},                  // rise ends at 0.5
      {130 * h, 0, 0, 0.5},                      // spiral starts at theta = 0
      {630 * h - 1, 0.6 * th_max, 0.0, 0.5 + 0.3 * th_max},  // theta = 4 pi
      {630 * h, 0.6 * th_max, 0.0, 0.5 + 0.3 * th_max},      // reverse run starts there
      {1130 * h - 1, 0, 0, 0.5},                 // and ends at theta = 0
      {1130 * h, 0, 0, 0.5},                     // past the end: hold the last point
      {4000000000u, 0, 0, 0.5},
  };
  for (const Case& c : cases) {
    float y[3];
    eval(p, c.k, y);
    EXPECT_NEAR(y[0], 1.0 + 2.0 * c.x, 2e-4) << c.k;
    EXPECT_NEAR(y[1], -2.0 + 2.0 * c.y, 2e-4) << c.k;
    EXPECT_NEAR(y[2], 0.5 + 2.0 * c.z, 2e-4) << c.k;
  }
  EXPECT_EQ(reference_length(p), 1130u * h);
}

TEST(Reference, SwirlInteriorPointsAndReverseSymmetry) {
  RefParams p = base(RefKind::Swirl);
  p.c[0] = p.c[1] = p.c[2] = 0.0f;
  for (uint32_t i : {1u, 100u, 250u, 498u}) {
    const double th = 4.0 * kPi * i / 499.0;
    float y[3], r[3];
    eval(p, (130 + i) * p.hold + 3, y);  // inside the hold of point i
    EXPECT_NEAR(y[0], 0.6 * th * std::cos(th), 2e-4) << i;
    EXPECT_NEAR(y[1], 0.6 * th * std::sin(th), 2e-4) << i;
    EXPECT_NEAR(y[2], 0.5 + 0.3 * th, 2e-4) << i;
    eval(p, (1129 - i) * p.hold, r);  // same point on the way back
    for (int a = 0; a < 3; ++a) EXPECT_FLOAT_EQ(r[a], y[a]);
  }
}

TEST(Reference, StepLevelsHoldAndEnd) {
  RefParams p{};
  p.kind = RefKind::Step;
  p.hold = 1000;
  p.level_count = 3;
  p.levels[0] = 0.5f;
  p.levels[1] = 1.0f;
  p.levels[2] = 2.0f;
  float y[3] = {-9.0f, -9.0f, -9.0f};
  reference_at(p, nullptr, 0, y, 1);
  EXPECT_FLOAT_EQ(y[0], 0.5f);
  EXPECT_FLOAT_EQ(y[1], -9.0f);  // n = 1 writes one value
  reference_at(p, nullptr, 999, y, 1);
  EXPECT_FLOAT_EQ(y[0], 0.5f);
  reference_at(p, nullptr, 1000, y, 1);
  EXPECT_FLOAT_EQ(y[0], 1.0f);
  reference_at(p, nullptr, 2999, y, 1);
  EXPECT_FLOAT_EQ(y[0], 2.0f);
  reference_at(p, nullptr, 1000000, y, 1);
  EXPECT_FLOAT_EQ(y[0], 2.0f);
  EXPECT_EQ(reference_length(p), 3000u);
  p.c[0] = 0.25f;
  reference_at(p, nullptr, 1500, y, 1);
  EXPECT_FLOAT_EQ(y[0], 1.25f);
}

TEST(Reference, TablePointsHoldMissingAxesAndEnd) {
  const float pts[4 * 2] = {1, 2, 3, 4, 5, 6, 7, 8};
  const ReferenceTable t{pts, 4, 2};
  RefParams p = base(RefKind::Table);
  p.hold = 3;
  float y[3];
  eval(p, 0, y, &t);
  EXPECT_FLOAT_EQ(y[0], 1.0f);
  EXPECT_FLOAT_EQ(y[1], 2.0f);
  EXPECT_FLOAT_EQ(y[2], 0.5f);  // axis the table lacks: the centre
  eval(p, 5, y, &t);
  EXPECT_FLOAT_EQ(y[0], 3.0f);
  eval(p, 11, y, &t);
  EXPECT_FLOAT_EQ(y[0], 7.0f);
  EXPECT_FLOAT_EQ(y[1], 8.0f);
  eval(p, 12, y, &t);  // past the end
  EXPECT_FLOAT_EQ(y[0], 7.0f);
  eval(p, UINT32_MAX, y, &t);
  EXPECT_FLOAT_EQ(y[1], 8.0f);
  EXPECT_EQ(reference_length(p, &t), 12u);
  // No table: hold the centre rather than read anything.
  eval(p, 5, y, nullptr);
  EXPECT_FLOAT_EQ(y[0], 1.0f);
  EXPECT_FLOAT_EQ(y[1], -2.0f);
  EXPECT_EQ(reference_length(p, nullptr), 0u);
}

TEST(Reference, HoldIsTheCentre) {
  const RefParams p = base(RefKind::Hold);
  float y[3];
  eval(p, 123456, y);
  EXPECT_FLOAT_EQ(y[0], 1.0f);
  EXPECT_FLOAT_EQ(y[1], -2.0f);
  EXPECT_FLOAT_EQ(y[2], 0.5f);
}

TEST(Reference, WritesAtMostThreeAndFiniteForAnyK) {
  const float pts[3] = {1, 2, 3};
  const ReferenceTable t{pts, 1, 3};
  for (int kind = 0; kind < kRefKindCount; ++kind) {
    RefParams p = base(static_cast<RefKind>(kind));
    p.level_count = 3;
    p.hold = 0;  // acts as 1
    for (uint32_t k : {0u, 1u, 29u, 1129u, 1130u, 65535u, 16777216u, UINT32_MAX}) {
      float y[6] = {-7, -7, -7, -7, -7, -7};
      reference_at(p, &t, k, y, 5);
      for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(y[i])) << kind << " " << k;
      EXPECT_FLOAT_EQ(y[3], -7.0f);
      EXPECT_FLOAT_EQ(y[4], -7.0f);
    }
  }
  float y = -7.0f;
  reference_at(base(RefKind::Infinity), nullptr, 3, &y, 0);
  EXPECT_FLOAT_EQ(y, -7.0f);
}

TEST(Reference, DegenerateAmplitudesStayFinite) {
  RefParams p = base(RefKind::Pringle);
  p.B = 0.0f;
  p.lambda = 0.0f;
  float y[3];
  eval(p, 10, y);
  for (float v : y) EXPECT_TRUE(std::isfinite(v));
}

TEST(Reference, CheckRejectsWhatCannotRun) {
  EXPECT_EQ(reference_check(base(RefKind::Infinity)), nullptr);
  EXPECT_EQ(reference_check(base(RefKind::Swirl)), nullptr);
  RefParams p = base(RefKind::Pringle);
  EXPECT_EQ(reference_check(p), nullptr);
  p.lambda = 0.0f;
  EXPECT_NE(reference_check(p), nullptr);
  p = base(RefKind::Infinity);
  p.omega = NAN;
  EXPECT_NE(reference_check(p), nullptr);
  p = base(RefKind::Step);
  p.level_count = 0;
  EXPECT_NE(reference_check(p), nullptr);
  p.level_count = 4;
  EXPECT_NE(reference_check(p), nullptr);
  p.level_count = 2;
  EXPECT_EQ(reference_check(p), nullptr);
  p = base(RefKind::Table);
  EXPECT_NE(reference_check(p, nullptr), nullptr);
  const float bad[2] = {1.0f, INFINITY};
  const ReferenceTable t{bad, 1, 2};
  EXPECT_NE(reference_check(p, &t), nullptr);
  const ReferenceTable ok{bad, 1, 1};
  EXPECT_EQ(reference_check(p, &ok), nullptr);
}

}  // namespace
}  // namespace nlsoft

// The references' sin and cos (shared/sincos.hpp) against double precision,
// with the bound the header states.
TEST(SinCos, AbsoluteErrorBelowStatedBound) {
  double worst = 0, worst_far = 0;
  for (double x = -1e5; x <= 1e5; x += 0.37) {
    const float xf = float(x);
    const nlsoft::SinCos sc = nlsoft::sincos_fast(xf);
    const double e = std::max(std::fabs(double(sc.s) - std::sin(double(xf))), std::fabs(double(sc.c) - std::cos(double(xf))));
    if (std::fabs(x) <= 6000)
      worst = std::max(worst, e);
    else
      worst_far = std::max(worst_far, e / std::fabs(x));
  }
  EXPECT_LT(worst, 2e-7);
  EXPECT_LT(worst_far, 3e-8);
  for (float x : {0.0f, 1e-30f, 1.5707964f, 3.1415927f, -4.712389f, 1e6f, -3e7f}) {
    const nlsoft::SinCos sc = nlsoft::sincos_fast(x);
    EXPECT_NEAR(sc.s * sc.s + sc.c * sc.c, 1.0f, 1e-6f) << x;
  }
  EXPECT_TRUE(std::isnan(nlsoft::sincos_fast(NAN).s));
  EXPECT_TRUE(std::isnan(nlsoft::sincos_fast(INFINITY).c));
}

// The references' remainder (shared/remainder.hpp) is std::fmod's, bit for
// bit: step counts over periods (periodic_phase), phases far past 2 pi
// (sincos_fast), and floats of any exponent against each other.
TEST(FmodExact, SameBitsAsStdFmod) {
  auto same = [](float x, float y) {
    const float want = std::fmod(x, y), got = nlsoft::fmod_exact(x, y);
    return std::signbit(want) == std::signbit(got) && (want == got || (std::isnan(want) && std::isnan(got)));
  };
  for (uint32_t k = 0; k < 20000; k += 7)
    for (float lambda : {1.0f, 3.0f, 130.0f, 780.5f, 1234.567f, 0.3f})
      EXPECT_TRUE(same(float(k), lambda)) << k << " mod " << lambda;
  for (float k : {16777215.0f, 16777216.0f, 9999999.0f})
    EXPECT_TRUE(same(k, 1234.567f)) << k;
  nlsoft::Rng rng(57);
  for (int i = 0; i < 100000; ++i) {
    const uint32_t bx = rng.next_u32(), by = rng.next_u32() & 0x7fffffffu;
    float x, y;
    std::memcpy(&x, &bx, 4);
    std::memcpy(&y, &by, 4);
    if (!std::isfinite(x) || !std::isfinite(y) || y == 0.0f) continue;
    ASSERT_TRUE(same(x, y)) << x << " mod " << y;
  }
  for (float x : {-0.0f, 0.0f, -5.5f, 5.5f, 6.28318531f, -1e30f, 3.4e38f})
    EXPECT_TRUE(same(x, 6.28318531f)) << x;
  EXPECT_TRUE(std::isnan(nlsoft::fmod_exact(INFINITY, 1.0f)));
  EXPECT_TRUE(std::isnan(nlsoft::fmod_exact(NAN, 1.0f)));
}
