#pragma once
// Elementary functions whose results are fixed when the program is built:
// exp, expm1, log, tanh, sigmoid, sin, cos, pow, written here from IEEE
// basic operations (+ - * / are exactly rounded) and exponent-bit handling.
//
// Why hand-written: glibc picks the code of exp, log, pow, sin, cos, tanh,
// expm1 ... at load time by CPU feature (ifunc: FMA, AVX2 variants), and the
// variants differ in the last bit. A model trained on one x86-64 CPU then
// differed from the same binary's model on another (and with
// GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F on the same one:
// tests/app/model/test_cpu_independence.sh). No Debian library gives
// results fixed at build time (libm, libmvec, Eigen's scalar paths all call
// glibc; CRlibm/CORE-MATH are not packaged), so training, the simulated
// plants and the metrics call these instead. Built with -ffp-contract=off
// (top-level CMakeLists.txt) nothing here is fused either.
//
// Accuracy (tests/shared/test_fixed_math.cpp measures it against long
// double std:: over dense sweeps): about 1 ulp for the double versions
// (pow a few ulps when |y log x| is large). The float versions compute in
// double and round once, so they are the correctly rounded float but for
// about one argument in 2^28: nearly always what glibc's expf/sinf gave.
//
// On the MCU (__arm__, arm-none-eabi) the float versions stay newlib's
// std:: functions: the Cortex-M4F has no double FPU, newlib does not
// dispatch by CPU, and the images keep their size and step time.
// Header-only, no heap, no exceptions.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#if defined(__arm__) || defined(__thumb__)
#define NLSOFT_FIXED_MATH_FLOAT_FROM_STD 1
#else
#define NLSOFT_FIXED_MATH_FLOAT_FROM_STD 0
#endif

namespace nlsoft::fixed_math {

namespace detail {

inline uint64_t bits_of(double x) {
  uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

inline double from_bits(uint64_t b) {
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

// 2^k for -1022 <= k <= 1023, straight into the exponent bits.
inline double pow2(int k) { return from_bits(uint64_t(k + 1023) << 52); }

// p * 2^k rounded once, for any k that keeps the product finite or lets it
// underflow (two exact scalings, then one that may round into subnormals).
inline double scale(double p, int k) {
  if (k > 1023) return p * pow2(1023) * pow2(k - 1023);
  if (k < -1022) return p * pow2(k + 600) * pow2(-600);
  return p * pow2(k);
}

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ln 2 = kLn2Hi + kLn2Lo; kLn2Hi has 32 significant bits, so k * kLn2Hi is
// exact for |k| < 2^21.
inline constexpr double kLn2Hi = 0x1.62e42feep-1;
inline constexpr double kLn2Lo = 0x1.a39ef35793c76p-33;
inline constexpr double kInvLn2 = 0x1.71547652b82fep0;

// Dekker's exact product a * b = hi + lo with basic operations only (no
// fma: it would not be fixed at build time either).
// T is double, or lanes of doubles (fixed_math_lanes.hpp): the same
// operations on each lane, so the same bits.
template <class T>
inline void two_prod(T a, T b, T& hi, T& lo) {
  constexpr double kSplit = 134217729.0;  // 2^27 + 1
  const T ca = kSplit * a, cb = kSplit * b;
  const T ah = ca - (ca - a), al = a - ah;
  const T bh = cb - (cb - b), bl = b - bh;
  hi = a * b;
  lo = ((ah * bh - hi) + ah * bl + al * bh) + al * bl;
}

// e^(r + c) - 1 = hi + lo for |r| <= ln2 / 2 + 2^-30, |c| <= ulp(r):
// Taylor series to r^15 (truncation below 3e-19 relative), r added last
// with the rounding of that sum carried in lo.
template <class T>
inline void expm1_reduced(T r, T c, T& hi, T& lo) {
  T q = T{} + 1.0 / 1307674368000.0;  // 1/15! (T{} + : as a T; exact)
  q = q * r + 1.0 / 87178291200.0;
  q = q * r + 1.0 / 6227020800.0;
  q = q * r + 1.0 / 479001600.0;
  q = q * r + 1.0 / 39916800.0;
  q = q * r + 1.0 / 3628800.0;
  q = q * r + 1.0 / 362880.0;
  q = q * r + 1.0 / 40320.0;
  q = q * r + 1.0 / 5040.0;
  q = q * r + 1.0 / 720.0;
  q = q * r + 1.0 / 120.0;
  q = q * r + 1.0 / 24.0;
  q = q * r + 1.0 / 6.0;
  q = q * r + 0.5;
  const T t = r * r * q;  // |t| < |r| / 4: fast two-sum below is exact
  hi = r + t;
  // e^(r + c) - 1 = (e^r - 1) + c e^r to 2^-100
  lo = ((r - hi) + t) + c * (1.0 + hi);
}

// x = k ln2 + r + c with |r| <= ln2/2 (a little more at the rounding
// boundary), c the rounding error of r (and any extra low part of x); x
// finite and |x| < 800.
// k is returned as a double (floor_of: std::floor, or the lanes' own).
inline double floor_of(double y) { return std::floor(y); }

#if !NLSOFT_FIXED_MATH_FLOAT_FROM_STD  // the lanes serve the host's training
// Four doubles as one value (the GCC/Clang vector extension): + - * / act
// on each lane as the scalar operation does, exactly rounded and never
// fused (-ffp-contract=off), so a kernel written for T gives each lane the
// bits the scalar call gives. Without AVX the compiler runs each operation
// as two SSE2 halves, which still hides most of a Horner chain's latency.
// Declared here, before the kernels, because a vector type has no
// namespace for argument-dependent lookup to find its floor_of in.
using Lanes = double __attribute__((vector_size(32)));
using LaneBits = int64_t __attribute__((vector_size(32)));
inline constexpr int kLanes = 4;

// floor for |y| < 2^51: rounded to an integer by adding and taking away
// 1.5 * 2^52 (exact there), less one where that rounded up. Equal to
// std::floor but for -0, which y = x / ln2 + 0.5 never is.
inline Lanes floor_of(Lanes y) {
  const Lanes t = (y + 0x1.8p52) - 0x1.8p52;
  const Lanes one = Lanes{} + 1.0;
  return t - Lanes(LaneBits(one) & (t > y));
}
#endif

template <class T>
inline T reduce_ln2_k(T x, T extra, T& r, T& c) {
  const T fk = floor_of(x * kInvLn2 + 0.5);
  const T hi = x - fk * kLn2Hi;  // exact: fk * kLn2Hi is, and x is near it
  const T lo = fk * kLn2Lo;
  r = hi - lo;
  c = ((hi - r) - lo) + extra;
  return fk;
}

inline void reduce_ln2(double x, double extra, int& k, double& r, double& c) {
  k = int(reduce_ln2_k(x, extra, r, c));
}

// e^(x + extra), |extra| <= 2^-40 |x|: extra carries the low half of a
// double-double argument (pow).
inline double exp_dd(double x, double extra) {
  if (x != x) return x + x;
  if (x > 709.782712893384) return kInf;
  if (x < -745.1332191019412) return 0.0;
  int k;
  double r, c;
  reduce_ln2(x, extra, k, r, c);
  double eh, el;
  expm1_reduced(r, c, eh, el);
  const double p1 = 1.0 + eh;  // 1 > |eh|: fast two-sum
  const double p = p1 + (((1.0 - p1) + eh) + el);
  return scale(p, k);
}

// log x = L_hi + L_lo to about 2^-65 relative, x finite and > 0:
// x = 2^e m, m in [sqrt(1/2), sqrt(2)), f = m - 1, s = f / (2 + f),
// log m = 2 atanh s = 2s + s * R(s^2), and 2s kept in two parts.
inline void log_parts(double x, double& L_hi, double& L_lo) {
  int e = 0;
  if (x < 0x1p-1022) {  // subnormal: make it normal first
    x *= 0x1p54;
    e = -54;
  }
  uint64_t b = bits_of(x);
  e += int((b >> 52) & 0x7ff) - 1023;
  b = (b & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL;
  double m = from_bits(b);  // [1, 2)
  if (m > 1.4142135623730951) {
    m *= 0.5;  // exact
    ++e;
  }
  const double f = m - 1.0;  // exact (Sterbenz)
  // d = 2 + f exactly as dh + dl
  const double dh = 2.0 + f;
  const double dl = f - (dh - 2.0);
  // s = f / d as sh + sl
  const double sh = f / dh;
  double ph, pl;
  two_prod(sh, dh, ph, pl);
  const double sl = ((f - ph) - pl - sh * dl) / dh;
  // R(z) = sum_{k>=1} 2 z^k / (2k + 1), z = s^2 <= 0.0295: to z^12
  // (truncation below 3e-20 of log m)
  const double z = sh * sh;
  double R = 2.0 / 25.0;
  R = R * z + 2.0 / 23.0;
  R = R * z + 2.0 / 21.0;
  R = R * z + 2.0 / 19.0;
  R = R * z + 2.0 / 17.0;
  R = R * z + 2.0 / 15.0;
  R = R * z + 2.0 / 13.0;
  R = R * z + 2.0 / 11.0;
  R = R * z + 2.0 / 9.0;
  R = R * z + 2.0 / 7.0;
  R = R * z + 2.0 / 5.0;
  R = R * z + 2.0 / 3.0;
  R *= z;
  // log m = 2 sh + (2 sl + sh R); plus e ln2 = e kLn2Hi (exact) + e kLn2Lo
  const double fe = double(e);
  const double a = fe * kLn2Hi;
  const double tail = 2.0 * sl + sh * R + fe * kLn2Lo;
  const double two_s = 2.0 * sh;  // exact
  // a + two_s in two parts (Knuth's two-sum: either may be the larger)
  const double s1 = a + two_s;
  const double bb = s1 - a;
  const double err = (a - (s1 - bb)) + (two_s - bb);
  L_hi = s1 + (err + tail);
  L_lo = (err + tail) - (L_hi - s1);
}

// x = n pi/2 + r + c, |r| <= pi/4 (a little more at the rounding boundary)
// for |x| < 2^19 pi/2: pi/2 in four parts, the first three of 33 bits so
// n times each is exact for |n| < 2^20 (Cody-Waite, as fdlibm).
inline void reduce_pio2_medium(double x, int& n, double& r, double& c) {
  constexpr double kP1 = 0x1.921fb544p0;
  constexpr double kP2 = 0x1.0b4611a6p-34;
  constexpr double kP3 = 0x1.3198a2ep-69;
  constexpr double kP4 = 0x1.b839a252049c1p-104;
  const double fn = std::floor(x * 0x1.45f306dc9c883p-1 + 0.5);  // x 2/pi
  n = int(fn);
  const double a = x - fn * kP1;  // exact
  const double w = fn * kP2;      // exact
  const double t = a - w;
  const double bb = t - a;
  const double err = (a - (t - bb)) + (-w - bb);  // a - w = t + err exactly
  const double low = err - fn * kP3 - fn * kP4;
  r = t + low;
  c = low - (r - t);
}

// For |x| >= 2^19 pi/2: Payne-Hanek. |x| = X 2^E with X a 53-bit
// integer, split in 24-bit digits x_i; 2/pi = sum w_j 2^(-24 (j+1)) with
// w_j its 24-bit words (fdlibm's ipio2). x 2/pi = sum x_i w_j 2^(E + 24 (1 -
// i - j)); the products worth 4 or more drop out mod 4, twelve columns
// below are kept (288 bits: more than the 2^-61 x can come to a multiple
// of pi/2, plus 53). Every product and column sum is an integer below
// 2^50, so the sums are exact; the carries are integer arithmetic.
inline void reduce_pio2_large(double x, int& n, double& r, double& c) {
  static constexpr int32_t kTwoOverPi[] = {
      0xA2F983, 0x6E4E44, 0x1529FC, 0x2757D1, 0xF534DD, 0xC0DB62, 0x95993C, 0x439041, 0xFE5163,
      0xABDEBB, 0xC561B7, 0x246E3A, 0x424DD2, 0xE00649, 0x2EEA09, 0xD1921C, 0xFE1DEB, 0x1CB129,
      0xA73EE8, 0x8235F5, 0x2EBB44, 0x84E99C, 0x7026B4, 0x5F7E41, 0x3991D6, 0x398353, 0x39F49C,
      0x845F8B, 0xBDF928, 0x3B1FF8, 0x97FFDE, 0x05980F, 0xEF2F11, 0x8B5A0A, 0x6D1F6D, 0x367ECF,
      0x27CB09, 0xB74F46, 0x3F669E, 0x5FEA2D, 0x7527BA, 0xC7EBE5, 0xF17B3D, 0x0739F7, 0x8A5292,
      0xEA6BFB, 0x5FB11F, 0x8D5D08, 0x560330, 0x46FC7B, 0x6BABF0, 0xCFBC20, 0x9AF436, 0x1DA9E3,
      0x91615E, 0xE61B08, 0x659985, 0x5F14A0, 0x68408D, 0xFFD880, 0x4D7327, 0x310606, 0x1556CA,
      0x73A8C9, 0x60E27B, 0xC08C6B,
  };
  constexpr int kWords = int(sizeof kTwoOverPi / sizeof kTwoOverPi[0]);
  constexpr int kCols = 12;
  const bool neg = x < 0.0;
  const uint64_t b = bits_of(neg ? -x : x);
  const int E = int((b >> 52) & 0x7ff) - 1075;
  const uint64_t X = (b & 0x000fffffffffffffULL) | 0x0010000000000000ULL;
  const int64_t xd[3] = {int64_t(X >> 48), int64_t((X >> 24) & 0xffffff), int64_t(X & 0xffffff)};
  // first: the smallest i + j whose products are worth less than 4, so
  // column k (i + j = first + k) is worth 2^(W - 24 k), -22 <= W <= 1
  int first = 0;
  while (E + 24 * (1 - first) > 1) ++first;
  const int W = E + 24 * (1 - first);
  int64_t col[kCols];
  for (int k = 0; k < kCols; ++k) {
    int64_t acc = 0;
    for (int i = 0; i < 3; ++i) {
      const int j = first + k - i;
      if (j >= 0 && j < kWords) acc += xd[i] * int64_t(kTwoOverPi[j]);
    }
    col[k] = acc;
  }
  // 24-bit digits from the bottom; the carry out of the top is worth 2^(W
  // + 24) >= 4 and drops out.
  int64_t carry = 0;
  for (int k = kCols - 1; k >= 0; --k) {
    const int64_t v = col[k] + carry;
    col[k] = v & 0xffffff;
    carry = v >> 24;
  }
  // the integer part mod 4 and the fraction as hi + lo. Digit k is worth
  // 2^(W - 24 k) a unit: digit 0 holds bits from 2^-22 up, digit 1 (when
  // W = 1) the bit worth 1. Each fraction piece is below the previous
  // one's unit, so fast two-sum is exact.
  int q = 0;
  double hi = 0.0, lo = 0.0;
  for (int k = 0; k < kCols; ++k) {
    const int we = W - 24 * k;
    int64_t frac = col[k];
    if (we >= 0) {
      q += int((col[k] << we) & 3);
      continue;
    }
    if (we > -24) {
      q += int((col[k] >> -we) & 3);
      frac = col[k] & ((int64_t(1) << -we) - 1);
    }
    const double term = double(frac) * pow2(we);
    const double s1 = hi + term;
    lo += term - (s1 - hi);
    hi = s1;
  }
  // to the nearest quadrant: fraction in [-1/2, 1/2)
  if (hi + lo >= 0.5) {
    hi -= 1.0;  // exact
    ++q;
  }
  const double fh = hi + lo;
  const double fl = lo - (fh - hi);
  // r = (fh + fl) pi/2 in two parts
  constexpr double kPio2Hi = 0x1.921fb54442d18p0;
  constexpr double kPio2Lo = 0x1.1a62633145c07p-54;
  double ph, pl;
  two_prod(fh, kPio2Hi, ph, pl);
  pl += fh * kPio2Lo + fl * kPio2Hi;
  r = ph + pl;
  c = pl - (r - ph);
  if (neg) {
    r = -r;
    c = -c;
    q = -q;
  }
  n = q & 3;
}

inline void reduce_pio2(double x, int& n, double& r, double& c) {
  if (std::fabs(x) < 823549.6) {  // 2^19 pi/2
    reduce_pio2_medium(x, n, r, c);
  } else {
    reduce_pio2_large(x, n, r, c);
  }
}

// sin(r + c), |r| <= pi/4 + small, |c| <= ulp(r): Taylor to r^19
// (truncation below 1e-19 relative).
inline double sin_reduced(double r, double c) {
  const double z = r * r;
  double p = -1.0 / 121645100408832000.0;  // -1/19!
  p = p * z + 1.0 / 355687428096000.0;
  p = p * z - 1.0 / 1307674368000.0;
  p = p * z + 1.0 / 6227020800.0;
  p = p * z - 1.0 / 39916800.0;
  p = p * z + 1.0 / 362880.0;
  p = p * z - 1.0 / 5040.0;
  p = p * z + 1.0 / 120.0;
  p = p * z - 1.0 / 6.0;
  // sin(r + c) = sin r + c cos r, cos r = 1 - z/2 to what c needs
  return r + (r * z * p + c * (1.0 - 0.5 * z));
}

// cos(r + c): Taylor to r^20 (truncation below 1e-20), 1 - z/2 with its
// rounding error carried (fdlibm's trick).
inline double cos_reduced(double r, double c) {
  const double z = r * r;
  double q = 1.0 / 2432902008176640000.0;  // 1/20!
  q = q * z - 1.0 / 6402373705728000.0;
  q = q * z + 1.0 / 20922789888000.0;
  q = q * z - 1.0 / 87178291200.0;
  q = q * z + 1.0 / 479001600.0;
  q = q * z - 1.0 / 3628800.0;
  q = q * z + 1.0 / 40320.0;
  q = q * z - 1.0 / 720.0;
  q = q * z + 1.0 / 24.0;
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  return w + (((1.0 - w) - hz) + (z * z * q - r * c));
}

// e^x - 1 = hi + lo for -40 <= x <= 40: x = k ln2 + r + c, e^x - 1 =
// (2^k - 1) + 2^k (e^(r + c) - 1), both terms exact (2^k - 1 is for k <=
// 58), summed with the rounding error kept.
inline void expm1_dd(double x, double& hi, double& lo) {
  int k;
  double r, c;
  reduce_ln2(x, 0.0, k, r, c);
  double eh, el;
  expm1_reduced(r, c, eh, el);
  if (k == 0) {
    hi = eh;
    lo = el;
    return;
  }
  const double s2k = pow2(k);
  const double a = s2k - 1.0, b = s2k * eh;
  const double s1 = a + b;  // two-sum: either may be the larger
  const double bb = s1 - a;
  const double err = (a - (s1 - bb)) + (b - bb);
  hi = s1;
  lo = err + s2k * el;
}

inline bool is_integer(double y) { return std::floor(y) == y; }
inline bool is_odd_integer(double y) {
  // |y| >= 2^53: every double is even
  return std::fabs(y) < 0x1p53 && is_integer(y) && !is_integer(0.5 * y);
}

}  // namespace detail

inline double exp(double x) { return detail::exp_dd(x, 0.0); }

inline double expm1(double x) {
  if (x != x) return x + x;
  if (std::fabs(x) < 0x1p-54) return x;  // x + x^2/2 rounds to x (keeps -0)
  if (x > 40.0) return exp(x);    // the -1 is below a quarter ulp
  if (x < -40.0) return -1.0;     // e^x below half an ulp of 1
  double hi, lo;
  detail::expm1_dd(x, hi, lo);
  return hi + lo;
}

inline double log(double x) {
  if (x != x) return x + x;
  if (x < 0.0) return detail::kNaN;
  if (x == 0.0) return -detail::kInf;
  if (x == detail::kInf) return x;
  double hi, lo;
  detail::log_parts(x, hi, lo);
  return hi;
}

inline double tanh(double x) {
  if (x != x) return x + x;
  const double ax = std::fabs(x);
  double t;
  if (ax < 0x1p-28) return x;  // tanh x = x - x^3/3 rounds to x (keeps -0)
  if (ax >= 22.0) {
    t = 1.0;  // 1 - 2 e^-44 rounds to 1
  } else if (ax >= 1.0) {
    t = 1.0 - 2.0 / (expm1(2.0 * ax) + 2.0);
  } else {
    // tanh = -e / (e + 2), e = e^(-2|x|) - 1 in two parts, the quotient
    // refined once with its exact residual (Dekker)
    double eh, el;
    detail::expm1_dd(-2.0 * ax, eh, el);
    const double dh = 2.0 + eh;  // 2 > |eh|: fast two-sum
    const double dl = (eh - (dh - 2.0)) + el;
    const double q = eh / dh;
    double ph, pl;
    detail::two_prod(q, dh, ph, pl);
    t = -(q + (((eh - ph) - pl) + el - q * dl) / dh);
  }
  return x < 0.0 ? -t : t;
}

inline double sigmoid(double x) { return 1.0 / (1.0 + exp(-x)); }

inline double sin(double x) {
  if (!(x - x == 0.0)) return x - x;  // NaN, +-inf
  if (std::fabs(x) < 0x1p-27) return x;  // x^3/6 below half an ulp (keeps -0)
  int n;
  double r, c;
  detail::reduce_pio2(x, n, r, c);
  switch (n & 3) {
    case 0: return detail::sin_reduced(r, c);
    case 1: return detail::cos_reduced(r, c);
    case 2: return -detail::sin_reduced(r, c);
    default: return -detail::cos_reduced(r, c);
  }
}

inline double cos(double x) {
  if (!(x - x == 0.0)) return x - x;
  if (std::fabs(x) < 0x1p-27) return 1.0;
  int n;
  double r, c;
  detail::reduce_pio2(x, n, r, c);
  switch (n & 3) {
    case 0: return detail::cos_reduced(r, c);
    case 1: return -detail::sin_reduced(r, c);
    case 2: return -detail::cos_reduced(r, c);
    default: return detail::sin_reduced(r, c);
  }
}

// x^y as C99's pow (Annex F special cases), finite cases as
// e^(y log x) with log x and the product kept in two parts.
inline double pow(double x, double y) {
  using detail::kInf;
  using detail::kNaN;
  if (y == 0.0 || x == 1.0) return 1.0;
  if (x != x || y != y) return x + y;
  const double ay = std::fabs(y);
  const double ax = std::fabs(x);
  if (ay == kInf) {
    if (ax == 1.0) return 1.0;
    return (ax < 1.0) == (y < 0.0) ? kInf : 0.0;
  }
  const bool odd = detail::is_odd_integer(y);
  if (x == 0.0) {
    const double mag = y < 0.0 ? kInf : 0.0;
    return odd ? std::copysign(mag, x) : mag;
  }
  if (ax == kInf) {
    const double mag = (y < 0.0) ? 0.0 : kInf;
    return (x < 0.0 && odd) ? -mag : mag;
  }
  if (x < 0.0 && !detail::is_integer(y)) return kNaN;
  if (ay >= 0x1p64) {
    // an even integer; |log |x|| >= 2^-53 makes |y log |x|| >= 2^11
    if (ax == 1.0) return 1.0;
    return (ax < 1.0) == (y < 0.0) ? kInf : 0.0;
  }
  double lh, ll;
  detail::log_parts(ax, lh, ll);
  double ph, pl;
  detail::two_prod(y, lh, ph, pl);
  pl += y * ll;
  const double zh = ph + pl;
  const double zl = pl - (zh - ph);
  const double mag = detail::exp_dd(zh, zl);
  return (x < 0.0 && odd) ? -mag : mag;
}

// float versions: through the double ones, rounded once. On the MCU,
// newlib's (see the top of the file).
#if NLSOFT_FIXED_MATH_FLOAT_FROM_STD
inline float exp(float x) { return std::exp(x); }
inline float expm1(float x) { return std::expm1(x); }
inline float log(float x) { return std::log(x); }
inline float tanh(float x) { return std::tanh(x); }
inline float sin(float x) { return std::sin(x); }
inline float cos(float x) { return std::cos(x); }
inline float pow(float x, float y) { return std::pow(x, y); }
#else
inline float exp(float x) { return float(exp(double(x))); }
inline float expm1(float x) { return float(expm1(double(x))); }
inline float log(float x) { return float(log(double(x))); }
inline float tanh(float x) { return float(tanh(double(x))); }
inline float sin(float x) { return float(sin(double(x))); }
inline float cos(float x) { return float(cos(double(x))); }
inline float pow(float x, float y) { return float(pow(double(x), double(y))); }
#endif

#if !NLSOFT_FIXED_MATH_FLOAT_FROM_STD
namespace detail {

// 2^k for integers -1022 <= k <= 1023 held as doubles: k read from the
// low bits of k + 1.5 * 2^52, put straight into the exponent bits.
inline Lanes pow2_of(Lanes fk) {
  const LaneBits k = LaneBits(fk + 0x1.8p52) - LaneBits(Lanes{} + 0x1.8p52);
  return Lanes((k + 1023) << 52);
}

inline bool all_of(LaneBits m) {
  int64_t a = -1;
  for (int i = 0; i < kLanes; ++i) a &= m[i];
  return a != 0;
}

inline Lanes fabs_of(Lanes x) { return Lanes(LaneBits(x) & 0x7fffffffffffffffLL); }

// m ? a : b lane by lane, m all ones or all zeros (a comparison's result):
// in bits, which compilers keep in vector registers where ?: may not be.
inline Lanes select(LaneBits m, Lanes a, Lanes b) { return Lanes((LaneBits(a) & m) | (LaneBits(b) & ~m)); }

// expm1_dd on each lane, |x| <= 40.
[[gnu::always_inline]] inline void expm1_dd(Lanes x, Lanes& hi, Lanes& lo) {
  Lanes r, c;
  const Lanes fk = reduce_ln2_k(x, Lanes{}, r, c);
  Lanes eh, el;
  expm1_reduced(r, c, eh, el);
  const Lanes s2k = pow2_of(fk);
  const Lanes a = s2k - 1.0, b = s2k * eh;
  const Lanes s1 = a + b;
  const Lanes bb = s1 - a;
  const Lanes err = (a - (s1 - bb)) + (b - bb);
  const LaneBits k0 = fk == 0.0;
  hi = select(k0, eh, s1);
  lo = select(k0, el, err + s2k * el);
}

// exp_dd(x, 0) on each lane, |x| <= 700 (no overflow, no subnormal).
[[gnu::always_inline]] inline Lanes exp_of(Lanes x) {
  Lanes r, c;
  const Lanes fk = reduce_ln2_k(x, Lanes{}, r, c);
  Lanes eh, el;
  expm1_reduced(r, c, eh, el);
  const Lanes p1 = 1.0 + eh;
  const Lanes p = p1 + (((1.0 - p1) + eh) + el);
  return p * pow2_of(fk);
}

// tanh's two finite branches on each lane, 2^-28 <= |x| < 20 (so
// expm1(2|x|) is expm1_dd's sum): both formulas, the lane's own kept.
[[gnu::always_inline]] inline Lanes tanh_of(Lanes x) {
  const Lanes ax = fabs_of(x);
  const LaneBits big = ax >= 1.0;
  Lanes eh, el;
  expm1_dd(select(big, 2.0 * ax, -2.0 * ax), eh, el);
  const Lanes t_big = 1.0 - 2.0 / ((eh + el) + 2.0);
  Lanes t = t_big;
  if (!all_of(big)) {  // the small formula only where a lane needs it
    const Lanes dh = 2.0 + eh;
    const Lanes dl = (eh - (dh - 2.0)) + el;
    const Lanes q = eh / dh;
    Lanes ph, pl;
    two_prod(q, dh, ph, pl);
    const Lanes t_small = -(q + (((eh - ph) - pl) + el - q * dl) / dh);
    t = select(big, t_big, t_small);
  }
  return select(x < 0.0, -t, t);
}

// f over x[0, n) into y (x == y allowed): four at a time where all four
// are in range (lanes), else one at a time (scalar).
template <class InRange, class OnLanes, class OnOne>
inline void each(const double* x, double* y, long n, InRange in_range, OnLanes on_lanes, OnOne on_one) {
  long i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    Lanes v;
    std::memcpy(&v, x + i, sizeof v);
    const LaneBits ok = in_range(v);
    if (all_of(ok)) {
      const Lanes out = on_lanes(v);
      std::memcpy(y + i, &out, sizeof out);
    } else {
      for (int j = 0; j < kLanes; ++j) y[i + j] = on_one(x[i + j]);
    }
  }
  for (; i < n; ++i) y[i] = on_one(x[i]);
}

}  // namespace detail

// y[i] = tanh(x[i]), sigmoid(x[i]) for i < n, the same bits as one call
// each, four lanes at a time: on 2^16 arguments in [-4, 4] (g++ -O2,
// x86-64 baseline, an EPYC core) sigmoid 16.3 -> 7.3 ns an argument, tanh
// 21.3 -> 16.8 (it keeps both of its formulas where a group mixes them).
inline void tanh_n(const double* x, double* y, long n) {
  detail::each(
      x, y, n,
      [](detail::Lanes v) {
        const detail::Lanes a = detail::fabs_of(v);
        return (a >= 0x1p-28) & (a < 20.0);
      },
      [](detail::Lanes v) { return detail::tanh_of(v); }, [](double v) { return tanh(v); });
}

inline void sigmoid_n(const double* x, double* y, long n) {
  detail::each(
      x, y, n, [](detail::Lanes v) { return detail::fabs_of(v) <= 700.0; },
      [](detail::Lanes v) { return 1.0 / (1.0 + detail::exp_of(-v)); }, [](double v) { return sigmoid(v); });
}
#endif

}  // namespace nlsoft::fixed_math
