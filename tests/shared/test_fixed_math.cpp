// shared/fixed_math.hpp against the long double std:: functions (x87, 64-bit
// significand: 11 bits more than a double, so the reference's own error is
// below 1/1000 ulp): the largest error in ulps over a dense sweep of each
// function's useful range, the special values C99's Annex F gives, and a
// hash of the results, which holds only while the bits are the same ones on
// every machine and build.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "shared/fixed_math.hpp"

namespace fm = nlsoft::fixed_math;

namespace {

// |got - want| in units of the last place of the double nearest want.
double ulp_error(double got, long double want) {
  const double w = double(want);
  if (std::isnan(w)) return std::isnan(got) ? 0.0 : 1e9;
  if (std::isinf(w)) return got == w ? 0.0 : 1e9;
  int e = 0;
  std::frexp(w, &e);
  const long double ulp = std::ldexp(1.0L, std::max(e - 53, -1074));
  return double(std::fabs(static_cast<long double>(got) - want) / ulp);
}

// The worst error of f against ref over n + 1 points from lo to hi, evenly
// spaced or (geometric) evenly in log; each point nudged one ulp off the
// grid so no run of round numbers hides a bad case.
template <class F, class R>
double worst_ulps(double lo, double hi, long n, F f, R ref, bool geometric = false) {
  double worst = 0;
  for (long i = 0; i <= n; ++i) {
    const double t = double(i) / double(n);
    double x = geometric ? lo * std::pow(hi / lo, t) : lo + (hi - lo) * t;
    x = std::nextafter(x, (i & 1) ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity());
    worst = std::max(worst, ulp_error(f(x), ref(static_cast<long double>(x))));
  }
  return worst;
}

constexpr long kPoints = 200000;

bool same(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return a == b && std::signbit(a) == std::signbit(b);
}

}  // namespace

TEST(FixedMath, ExpWithinOneUlp) {
  auto f = [](double x) { return fm::exp(x); };
  auto r = [](long double x) { return std::exp(x); };
  EXPECT_LT(worst_ulps(-745.0, 709.7, kPoints, f, r), 0.8);
  EXPECT_LT(worst_ulps(-2.0, 2.0, kPoints, f, r), 0.7);
  EXPECT_LT(worst_ulps(1e-18, 1.0, kPoints, f, r, true), 0.7);
  EXPECT_LT(worst_ulps(-745.13, -708.4, kPoints / 10, f, r), 1.0);  // subnormal results
}

TEST(FixedMath, Expm1WithinOneUlp) {
  auto f = [](double x) { return fm::expm1(x); };
  auto r = [](long double x) { return std::expm1(x); };
  EXPECT_LT(worst_ulps(-40.0, 709.0, kPoints, f, r), 1.1);
  EXPECT_LT(worst_ulps(-1.5, 1.5, kPoints, f, r), 0.9);
  EXPECT_LT(worst_ulps(1e-300, 1.0, kPoints, f, r, true), 0.9);
  EXPECT_LT(worst_ulps(-1.0, -1e-300, kPoints, f, r, true), 0.9);
}

TEST(FixedMath, LogWithinOneUlp) {
  auto f = [](double x) { return fm::log(x); };
  auto r = [](long double x) { return std::log(x); };
  EXPECT_LT(worst_ulps(1e-300, 1e300, kPoints, f, r, true), 0.6);
  EXPECT_LT(worst_ulps(0.5, 2.0, kPoints, f, r), 0.6);
  EXPECT_LT(worst_ulps(1.0 - 1e-6, 1.0 + 1e-6, kPoints, f, r), 0.6);
  EXPECT_LT(worst_ulps(5e-324, 2e-308, kPoints / 10, f, r, true), 0.6);  // subnormal arguments
}

TEST(FixedMath, TanhAndSigmoidWithinOneUlp) {
  auto f = [](double x) { return fm::tanh(x); };
  auto r = [](long double x) { return std::tanh(x); };
  EXPECT_LT(worst_ulps(-25.0, 25.0, kPoints, f, r), 1.0);
  EXPECT_LT(worst_ulps(1e-300, 2.0, kPoints, f, r, true), 1.0);  // near 0: through expm1
  EXPECT_LT(worst_ulps(-40.0, 40.0, kPoints, [](double x) { return fm::sigmoid(x); },
                       [](long double x) { return 1.0L / (1.0L + std::exp(-x)); }),
            2.5);  // e^-x within an ulp, then two roundings
}

// tanh_n and sigmoid_n (four lanes at a time) against one call each: the
// same bits over a dense sweep, at every branch's edge, on the special
// values and on runs whose length is no multiple of four, where a lane out
// of the lanes' range sends its group to the scalar calls.
TEST(FixedMath, ManyAtOnceGiveEachCallsBits) {
  std::vector<double> x;
  for (long i = 0; i <= 400000; ++i) {
    const double v = -30.0 + 60.0 * double(i) / 400000.0;
    x.push_back(std::nextafter(v, (i & 1) ? 1e300 : -1e300));
  }
  for (double e : {0x1p-28, 1.0, 0.5, 20.0, 22.0, 40.0, 700.0, 709.78, 745.2, 1e-300, 5e-324})
    for (double s : {-1.0, 1.0})
      for (int k = -3; k <= 3; ++k) {
        double v = s * e;
        for (int j = 0; j < std::abs(k); ++j) v = std::nextafter(v, k < 0 ? -1e300 : 1e300);
        x.push_back(v);
      }
  for (double v : {0.0, -0.0, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::quiet_NaN(), 1e300, -1e300})
    x.push_back(v);
  x.push_back(0.3);  // 400,001 + 154 + 7 + 1: no multiple of four
  ASSERT_NE(x.size() % 4, 0u);
  std::vector<double> t(x.size()), s(x.size());
  fm::tanh_n(x.data(), t.data(), long(x.size()));
  fm::sigmoid_n(x.data(), s.data(), long(x.size()));
  long differ = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!same(t[i], fm::tanh(x[i])) || !same(s[i], fm::sigmoid(x[i]))) {
      if (++differ <= 5) ADD_FAILURE() << "x = " << std::hexfloat << x[i] << ": tanh " << t[i] << " vs " << fm::tanh(x[i])
                                       << ", sigmoid " << s[i] << " vs " << fm::sigmoid(x[i]);
    }
  }
  EXPECT_EQ(differ, 0);
  // In place, as a network's activation runs.
  std::vector<double> in_place = x;
  fm::tanh_n(in_place.data(), in_place.data(), long(in_place.size()));
  for (size_t i = 0; i < x.size(); ++i) ASSERT_TRUE(same(in_place[i], t[i])) << i;
}

TEST(FixedMath, SinCosWithinOneUlpForEveryArgument) {
  auto s = [](double x) { return fm::sin(x); };
  auto rs = [](long double x) { return std::sin(x); };
  auto c = [](double x) { return fm::cos(x); };
  auto rc = [](long double x) { return std::cos(x); };
  EXPECT_LT(worst_ulps(-10.0, 10.0, kPoints, s, rs), 0.8);
  EXPECT_LT(worst_ulps(-10.0, 10.0, kPoints, c, rc), 0.8);
  EXPECT_LT(worst_ulps(1e-300, 1.0, kPoints, s, rs, true), 0.8);
  // Cody-Waite up to 2^19 pi/2, Payne-Hanek beyond
  EXPECT_LT(worst_ulps(-1e6, 1e6, kPoints, s, rs), 0.8);
  EXPECT_LT(worst_ulps(-1e6, 1e6, kPoints, c, rc), 0.8);
  EXPECT_LT(worst_ulps(8e5, 1e300, kPoints, s, rs, true), 0.8);
  EXPECT_LT(worst_ulps(8e5, 1e300, kPoints, c, rc, true), 0.8);
  // next to multiples of pi/2, where the reduction cancels most
  EXPECT_LT(ulp_error(fm::sin(M_PI), std::sin(static_cast<long double>(M_PI))), 0.6);
  EXPECT_LT(ulp_error(fm::cos(M_PI_2), std::cos(static_cast<long double>(M_PI_2))), 0.6);
  EXPECT_LT(ulp_error(fm::sin(1e22), std::sin(1e22L)), 0.6);
}

TEST(FixedMath, PowWithinAFewUlps) {
  // the reference gets the same double arguments (a long double literal
  // would be another number)
  const double e = 2.718281828459045, y137 = 1.37;
  EXPECT_LT(worst_ulps(1e-300, 1e200, kPoints, [&](double x) { return fm::pow(x, y137); },
                       [&](long double x) { return std::pow(x, static_cast<long double>(y137)); }, true),
            1.0);
  EXPECT_LT(worst_ulps(0.0, 1.0, kPoints, [](double u) { return fm::pow(1e12, u); },
                       [](long double u) { return std::pow(1e12L, u); }),
            1.0);
  // |y log x| up to 700: log x's last bits, times 700
  EXPECT_LT(worst_ulps(-700.0, 700.0, kPoints, [&](double y) { return fm::pow(e, y); },
                       [&](long double y) { return std::pow(static_cast<long double>(e), y); }),
            3.0);
  EXPECT_LT(worst_ulps(-1e100, -1e-100, kPoints, [](double x) { return fm::pow(x, 3.0); },
                       [](long double x) { return std::pow(x, 3.0L); }, true),
            1.0);
}

TEST(FixedMath, SpecialValuesAsAnnexF) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  // where the result is exact: signed zeros, infinities, NaN, x itself or
  // 1 for subnormal x
  for (double x : {0.0, -0.0, inf, -inf, nan, 1e-310, -1e-310, 5e-324}) {
    SCOPED_TRACE(x);
    EXPECT_TRUE(same(fm::exp(x), std::exp(x)));
    EXPECT_TRUE(same(fm::expm1(x), std::expm1(x)));
    EXPECT_TRUE(same(fm::log(x), std::log(x)));
    EXPECT_TRUE(same(fm::tanh(x), std::tanh(x)));
    EXPECT_TRUE(same(fm::sin(x), std::sin(x)));
    EXPECT_TRUE(same(fm::cos(x), std::cos(x)));
  }
  const double v[] = {0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 0.5, -0.5, 3.0, -3.0, 2.5, -2.5,
                      inf, -inf, nan, 1e308, -1e308, 0x1p70, -0x1p70, 5e-324};
  for (double x : v)
    for (double y : v) {
      SCOPED_TRACE(testing::Message() << "pow(" << x << ", " << y << ")");
      EXPECT_TRUE(same(fm::pow(x, y), std::pow(x, y)));
    }
  // overflow and underflow
  EXPECT_EQ(fm::exp(710.0), inf);
  EXPECT_EQ(fm::exp(-746.0), 0.0);
  EXPECT_EQ(fm::expm1(710.0), inf);
  EXPECT_EQ(fm::expm1(-746.0), -1.0);
  EXPECT_EQ(fm::tanh(710.0), 1.0);
  EXPECT_EQ(fm::tanh(-710.0), -1.0);
  EXPECT_TRUE(std::isnan(fm::log(-746.0)));
  EXPECT_EQ(fm::exp(709.78), std::exp(709.78));
  EXPECT_EQ(fm::exp(-745.0), std::exp(-745.0));  // the smallest subnormal
  EXPECT_EQ(fm::exp(-745.2), 0.0);
  EXPECT_EQ(fm::pow(10.0, 309.0), inf);
  EXPECT_EQ(fm::pow(10.0, -324.0), 0.0);
}

TEST(FixedMath, KnownValues) {
  EXPECT_EQ(fm::exp(1.0), 0x1.5bf0a8b145769p+1);  // e, correctly rounded
  EXPECT_EQ(fm::log(2.0), 0x1.62e42fefa39efp-1);  // ln 2
  EXPECT_EQ(fm::log(10.0), 0x1.26bb1bbb55516p+1);
  EXPECT_EQ(fm::sin(M_PI), 0x1.1a62633145c07p-53);  // pi - double(pi)
  EXPECT_EQ(fm::cos(M_PI), -1.0);
  EXPECT_EQ(fm::tanh(0.5), 0x1.d9353d7568af3p-2);
  EXPECT_EQ(fm::pow(2.0, 0.5), 0x1.6a09e667f3bcdp+0);  // sqrt 2
  EXPECT_EQ(fm::pow(-2.0, 3.0), -8.0);
}

// The float versions round the double result once: the correctly rounded
// float but for about one argument in 2^28, i.e. nearly always glibc's
// expf, sinf ... (which are correctly rounded almost everywhere too).
TEST(FixedMath, FloatVersionsAreTheCorrectlyRoundedFloat) {
  ASSERT_EQ(NLSOFT_FIXED_MATH_FLOAT_FROM_STD, 0);  // a host build computes them here
  long off = 0, count = 0;
  for (long i = 0; i <= 400000; ++i) {
    const float x = -80.0f + 160.0f * float(i) / 400000.0f;
    const long double lx = x;
    off += fm::exp(x) != float(std::exp(lx));
    off += fm::tanh(x) != float(std::tanh(lx));
    off += fm::sin(x) != float(std::sin(lx));
    off += fm::cos(x) != float(std::cos(lx));
    off += fm::expm1(x) != float(std::expm1(lx));
    const float p = std::fabs(x) + 1e-3f;
    off += fm::log(p) != float(std::log(static_cast<long double>(p)));
    off += fm::pow(p, 1.7f) != float(std::pow(static_cast<long double>(p), static_cast<long double>(1.7f)));
    count += 7;
  }
  EXPECT_LE(off, 2) << "of " << count;
}

// The point of the file: these bits, on every x86-64 CPU and build. A
// change to the code, or a build flag that changes rounding (contraction
// into fma, x87 arithmetic, -ffast-math), changes the hash.
TEST(FixedMath, ResultsAreTheRecordedBits) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](double v) {
    uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    h = (h ^ b) * 1099511628211ull;
  };
  for (long i = 0; i < 20000; ++i) {
    const double x = -30.0 + 60.0 * double(i) / 20000.0 + 1e-7;
    mix(fm::exp(x));
    mix(fm::expm1(x));
    mix(fm::log(std::fabs(x)));
    mix(fm::tanh(x));
    mix(fm::sin(x * 1e3));
    mix(fm::cos(x * 1e3));
    mix(fm::pow(std::fabs(x), 1.37));
    mix(double(fm::exp(float(x))));
  }
  EXPECT_EQ(h, 0x7c8373f7994ee463ull) << std::hex << h;
}
