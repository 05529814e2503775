// The identification run's excitation signals (shared/excitation.hpp): every
// input inside its limits whatever the seed, a seed repeats its sequence bit
// for bit and another seed gives another, and each signal keeps to its band.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "shared/excitation.hpp"
#include "shared/rng.hpp"

namespace nlsoft {
namespace {

constexpr int kM = 3;
// Asymmetric limits; the first input's neutral sits at its lower limit, the
// last one's near its upper limit.
const float kMin[kM] = {0.0f, -2.0f, 10.0f};
const float kMax[kM] = {1.0f, 6.0f, 12.0f};
const float kNeutral[kM] = {0.0f, 1.0f, 11.9f};
constexpr float kRate = 100.0f;

const ExcitationSignal kSignals[] = {ExcitationSignal::Steps, ExcitationSignal::Prbs, ExcitationSignal::Walk,
                                     ExcitationSignal::Chirp, ExcitationSignal::Aprbs};

std::vector<float> run(ExcitationSignal sig, uint32_t seed, bool joint, uint32_t steps, float amplitude = 1.0f,
                       float lo = 0.2f, float hi = 5.0f, bool mixed = false) {
  ExcitationSpec s;
  s.signal = sig;
  s.seed = seed;
  s.joint = joint;
  s.mixed = mixed;
  s.amplitude = amplitude;
  s.band_lo = lo;
  s.band_hi = hi;
  s.duration = steps;
  Excitation e;
  const ExcitationCheck c = e.configure(s, kRate, kMin, kMax, kNeutral, kM);
  EXPECT_EQ(c.status, Status::Ok);
  std::vector<float> out(size_t(steps) * kM);
  for (uint32_t k = 0; k < steps; ++k) e.next(&out[size_t(k) * kM]);
  EXPECT_TRUE(e.done());
  return out;
}

class EachSignal : public ::testing::TestWithParam<ExcitationSignal> {};

TEST_P(EachSignal, InputsStayInsideTheirLimitsForEverySeed) {
  for (uint32_t seed = 0; seed < 40; ++seed)
    for (int options = 0; options < 3; ++options)  // own streams, joint, mixed (prbs has none)
      for (float amplitude : {1.0f, 0.3f}) {
        if (options == 2 && GetParam() == ExcitationSignal::Prbs) continue;
        const std::vector<float> u = run(GetParam(), seed, options == 1, 2000, amplitude, 0.2f, 5.0f, options == 2);
        float lo[kM], hi[kM];
        for (int i = 0; i < kM; ++i) lo[i] = kMax[i], hi[i] = kMin[i];
        for (size_t k = 0; k < u.size(); ++k) {
          const size_t i = k % kM;
          ASSERT_TRUE(u[k] >= kMin[i] && u[k] <= kMax[i]) << "seed " << seed << " step " << k / kM << " input " << i;
          lo[i] = std::fmin(lo[i], u[k]), hi[i] = std::fmax(hi[i], u[k]);
        }
        // The window is amplitude x the range wide.
        for (int i = 0; i < kM; ++i) ASSERT_LE(hi[i] - lo[i], amplitude * (kMax[i] - kMin[i]) * 1.0001f);
      }
}

TEST_P(EachSignal, TheSameSeedRepeatsTheSequenceBitForBit) {
  const std::vector<float> a = run(GetParam(), 1234, false, 3000);
  const std::vector<float> b = run(GetParam(), 1234, false, 3000);
  ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
}

TEST_P(EachSignal, AnotherSeedGivesAnotherSequence) {
  const std::vector<float> a = run(GetParam(), 1, false, 3000);
  const std::vector<float> b = run(GetParam(), 2, false, 3000);
  size_t differ = 0;
  for (size_t k = 0; k < a.size(); ++k) differ += a[k] != b[k];
  EXPECT_GT(differ, a.size() / 4);
}

// With amplitude 1 every input's window is its whole range, so jointly the
// inputs sit at the same fraction of their ranges, and per input they do not.
TEST_P(EachSignal, PerInputStreamsDifferAndJointOnesMoveTogether) {
  const std::vector<float> own = run(GetParam(), 5, false, 3000);
  const std::vector<float> joint = run(GetParam(), 5, true, 3000);
  auto fraction = [](const std::vector<float>& u, size_t k, int i) {
    return (u[k * kM + size_t(i)] - kMin[i]) / (kMax[i] - kMin[i]);
  };
  size_t apart = 0;
  for (size_t k = 0; k < joint.size() / kM; ++k) {
    ASSERT_NEAR(fraction(joint, k, 1), fraction(joint, k, 0), 1e-5f) << "step " << k;
    ASSERT_NEAR(fraction(joint, k, 2), fraction(joint, k, 0), 1e-4f) << "step " << k;
    apart += std::fabs(fraction(own, k, 1) - fraction(own, k, 0)) > 1e-3f;
  }
  EXPECT_GT(apart, joint.size() / kM / 4);
}

TEST_P(EachSignal, UsesMostOfItsWindow) {
  const std::vector<float> u = run(GetParam(), 9, false, 20000);
  for (int i = 0; i < kM; ++i) {
    float lo = kMax[i], hi = kMin[i];
    for (size_t k = size_t(i); k < u.size(); k += kM) lo = std::fmin(lo, u[k]), hi = std::fmax(hi, u[k]);
    EXPECT_GT(hi - lo, 0.7f * (kMax[i] - kMin[i])) << "input " << i;
  }
}

std::string signal_name(const ::testing::TestParamInfo<ExcitationSignal>& info) {
  static const char* const kNames[] = {"Steps", "Prbs", "Walk", "Chirp", "Aprbs"};
  return kNames[int(info.param)];
}
INSTANTIATE_TEST_SUITE_P(Excitation, EachSignal, ::testing::ValuesIn(kSignals), signal_name);

// Zero crossings of the chirp around the middle of input 1's window give its
// frequency: band_lo at the start, band_hi at the end, between in between.
TEST(Excitation, TheChirpSweepsItsBand) {
  const float lo = 0.5f, hi = 8.0f;
  const uint32_t steps = 60000;  // 10 minutes at 100 Hz
  const std::vector<float> u = run(ExcitationSignal::Chirp, 3, false, steps, 1.0f, lo, hi);
  const float mid = 0.5f * (kMin[1] + kMax[1]);
  auto frequency = [&](uint32_t from, uint32_t to) {
    int crossings = 0;
    for (uint32_t k = from + 1; k < to; ++k)
      crossings += (u[size_t(k - 1) * kM + 1] < mid) != (u[size_t(k) * kM + 1] < mid);
    return float(crossings) / 2.0f / (float(to - from) / kRate);
  };
  const uint32_t w = 2000;  // 20 s windows
  EXPECT_NEAR(frequency(0, w), lo + (hi - lo) * 0.5f * w / steps, 0.1f);
  EXPECT_NEAR(frequency(steps / 2 - w / 2, steps / 2 + w / 2), 0.5f * (lo + hi), 0.15f);
  EXPECT_NEAR(frequency(steps - w, steps), hi - (hi - lo) * 0.5f * w / steps, 0.2f);
}

TEST(Excitation, PrbsBitsLastOneOverBandHiAndTheRegisterCoversBandLo) {
  ExcitationSpec s;
  s.signal = ExcitationSignal::Prbs;
  s.amplitude = 1.0f;
  s.band_lo = 0.05f;
  s.band_hi = 10.0f;  // 10 steps a bit at 100 Hz
  s.duration = 50000;
  Excitation e;
  ASSERT_EQ(e.configure(s, kRate, kMin, kMax, kNeutral, kM).status, Status::Ok);
  // One period, (2^bits - 1) bits of 10 steps, lasts at least 1 / band_lo = 20 s.
  EXPECT_GE(float((1u << e.prbs_bits()) - 1u) * 10.0f, kRate / s.band_lo);
  float u[kM], prev = 0.0f;
  uint32_t run_len = 0;
  for (uint32_t k = 0; k < s.duration; ++k) {
    e.next(u);
    EXPECT_TRUE(u[0] == kMin[0] || u[0] == kMax[0]);
    if (k > 0 && u[0] != prev) {
      EXPECT_EQ(run_len % 10u, 0u) << "step " << k;
      run_len = 0;
    }
    prev = u[0];
    ++run_len;
  }
}

TEST(Excitation, EveryPrbsRegisterHasTheMaximalPeriod) {
  for (int bits = 3; bits <= 16; ++bits) {
    const uint32_t taps = prbs_taps(bits), start = 1;
    uint32_t s = start, period = 0;
    do {
      const uint32_t bit = s & 1u;
      s >>= 1;
      if (bit) s ^= taps;
      ++period;
    } while (s != start && period < (1u << 17));
    EXPECT_EQ(period, (1u << bits) - 1u) << bits << " bits";
  }
}

// Per-input prbs streams are one maximal-length sequence, each input
// shifted from the one before: no two inputs equal, none the product (XOR)
// of others. Over one period every pattern of the m inputs' bits occurs,
// all 2^m of them where the register has more bits than there are inputs
// (all but all-low where it has exactly m: the register is never zero).
// Before, each input started the sequence at a random state: 6 inputs on
// a 63-bit register made two inputs equal on seeds 3 and 7 and left 32 of
// the 64 patterns on the others.
TEST(Excitation, PrbsInputsTakeEveryPatternOfTheirBitsOverAPeriod) {
  const float lo[kRigMaxM] = {0, 0, 0, 0, 0, 0, 0, 0}, hi[kRigMaxM] = {1, 1, 1, 1, 1, 1, 1, 1};
  for (int band_bits : {3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 16}) {
    for (int m = 1; m <= kRigMaxM; ++m) {
      for (uint32_t seed : {3u, 7u, 11u}) {
        ExcitationSpec s;
        s.signal = ExcitationSignal::Prbs;
        s.amplitude = 1.0f;
        s.seed = seed;
        s.band_hi = 0.5f * kRate;  // a bit every 2 steps
        // The shortest register whose period of 2-step bits covers 1/band_lo.
        s.band_lo = 1.001f * kRate / (2.0f * float((1u << band_bits) - 1u));
        s.duration = 1u << 18;
        Excitation e;
        ASSERT_EQ(e.configure(s, kRate, lo, hi, hi, m).status, Status::Ok);
        const int bits = e.prbs_bits();
        ASSERT_EQ(bits, std::max(band_bits, m)) << band_bits << " bits for the band, m " << m;
        std::vector<bool> seen(size_t(1) << m, false);
        float u[kRigMaxM];
        for (uint32_t k = 0; k < (1u << bits) - 1u; ++k) {
          e.next(u);
          uint32_t pattern = 0;
          for (int i = 0; i < m; ++i) pattern |= uint32_t(u[i] > 0.5f) << i;
          seen[pattern] = true;
          e.next(u);
        }
        const size_t patterns = size_t(std::count(seen.begin(), seen.end(), true));
        EXPECT_EQ(patterns, bits > m ? seen.size() : seen.size() - 1)
            << bits << "-bit register, m " << m << ", seed " << seed;
      }
    }
  }
}

TEST(Excitation, StepsHoldBetweenOneOverBandHiAndOneOverBandLo) {
  const std::vector<float> u = run(ExcitationSignal::Steps, 11, false, 30000, 1.0f, 0.5f, 4.0f);
  // 25 to 200 steps a level at 100 Hz; the last level may be cut short.
  uint32_t len = 1, longest = 0, shortest = 1u << 30;
  for (size_t k = 1; k < u.size() / kM; ++k) {
    if (u[k * kM] != u[(k - 1) * kM]) {
      longest = std::max(longest, len), shortest = std::min(shortest, len);
      len = 0;
    }
    ++len;
  }
  EXPECT_GE(shortest, 25u);
  EXPECT_LE(longest, 200u);
  EXPECT_GT(longest, 150u);
}

// The hold (in steps) of every level of input `i` but the last, cut short.
std::vector<uint32_t> holds(const std::vector<float>& u, int i) {
  std::vector<uint32_t> out;
  uint32_t len = 1;
  for (size_t k = 1; k < u.size() / kM; ++k) {
    if (u[k * kM + size_t(i)] != u[(k - 1) * kM + size_t(i)]) out.push_back(len), len = 0;
    ++len;
  }
  return out;
}

// aprbs switches where prbs does, at whole bits of 1/band_hi, its longest
// hold the register's longest run; unlike prbs it has a new level each
// time, filling the window; unlike steps most holds are a bit or two.
TEST(Excitation, AprbsHoldsAreWholePrbsBitsWithANewLevelInsideTheRangeEachTime) {
  const float lo = 0.05f, hi = 10.0f;  // 10 steps a bit at 100 Hz
  const uint32_t steps = 60000;
  const std::vector<float> u = run(ExcitationSignal::Aprbs, 21, false, steps, 1.0f, lo, hi);
  ExcitationSpec s;
  s.signal = ExcitationSignal::Aprbs, s.band_lo = lo, s.band_hi = hi, s.duration = steps;
  Excitation e;
  ASSERT_EQ(e.configure(s, kRate, kMin, kMax, kNeutral, kM).status, Status::Ok);
  const uint32_t bit = 10, longest_run = uint32_t(e.prbs_bits()) * bit;
  for (int i = 0; i < kM; ++i) {
    const std::vector<uint32_t> h = holds(u, i);
    ASSERT_GT(h.size(), 1000u) << "input " << i;
    size_t one_bit = 0;
    for (uint32_t len : h) {
      ASSERT_EQ(len % bit, 0u) << "input " << i;
      ASSERT_GE(len, bit);
      ASSERT_LE(len, longest_run);
      one_bit += len == bit;
    }
    // A maximal-length sequence's runs: half of them one bit long.
    EXPECT_NEAR(double(one_bit) / double(h.size()), 0.5, 0.05) << "input " << i;
    // More than two levels, spread over the window in all its tenths.
    std::vector<float> levels;
    for (size_t k = size_t(i); k < u.size(); k += kM) levels.push_back(u[k]);
    std::sort(levels.begin(), levels.end());
    levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
    EXPECT_GT(levels.size(), 500u) << "input " << i;
    int tenths[10] = {};
    for (float v : levels) ++tenths[std::min(9, int(10.0f * (v - kMin[i]) / (kMax[i] - kMin[i])))];
    for (int t = 0; t < 10; ++t) EXPECT_GT(tenths[t], 10) << "input " << i << " tenth " << t;
  }
  // The same switching instants as prbs of the same seed: aprbs only puts
  // other levels on them.
  const std::vector<float> p = run(ExcitationSignal::Prbs, 21, false, steps, 1.0f, lo, hi);
  for (size_t k = 1; k < steps; ++k)
    ASSERT_EQ(p[k * kM] != p[(k - 1) * kM], u[k * kM] != u[(k - 1) * kM]) << "step " << k;
}

// The arithmetic the firmware does, written out with the generator's parts
// (Rng, the register's taps): input 0's levels are the seed's uniform draws
// mapped into the window, bit for bit. Float and 32-bit integers only, no
// libm, as on the Cortex-M4F.
TEST(Excitation, AprbsIsTheSeedsDrawsMappedIntoTheWindowBitForBit) {
  const float lo = 0.05f, hi = 10.0f;
  const uint32_t seed = 77, steps = 3000;
  const std::vector<float> u = run(ExcitationSignal::Aprbs, seed, false, steps, 1.0f, lo, hi);
  Rng rng(seed ^ 0x9E3779B9u);  // input 0's stream
  ExcitationSpec s;
  s.signal = ExcitationSignal::Aprbs, s.band_lo = lo, s.band_hi = hi, s.duration = steps;
  Excitation e;
  ASSERT_EQ(e.configure(s, kRate, kMin, kMax, kNeutral, kM).status, Status::Ok);
  uint32_t lfsr = rng.next_u32() & ((1u << e.prbs_bits()) - 1u), last = 2;
  if (lfsr == 0) lfsr = 1;
  rng.uniform(-1.0f, 1.0f);  // the walk's start, drawn for every signal
  float level = 0.0f;
  for (uint32_t k = 0; k < steps; ++k) {
    if (k % 10 == 0) {
      const uint32_t bit = lfsr & 1u;
      lfsr >>= 1;
      if (bit) lfsr ^= prbs_taps(e.prbs_bits());
      if (bit != last) level = rng.uniform(-1.0f, 1.0f);
      last = bit;
    }
    // Input 0's window is its whole range [0, 1] (amplitude 1).
    const float want = kMin[0] + 0.5f * (level + 1.0f) * (kMax[0] - kMin[0]);
    ASSERT_EQ(std::memcmp(&u[size_t(k) * kM], &want, sizeof want), 0) << "step " << k;
  }
}

// Mixed: a shared stream under each input's own, so the inputs correlate
// clearly (about 0.75 for uniform levels) where own streams do not.
TEST(Excitation, MixedInputsShareACommonComponent) {
  auto correlation = [](const std::vector<float>& u, int a, int b) {
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    const double n = double(u.size() / kM);
    for (size_t k = 0; k < u.size() / kM; ++k) {
      const double x = (u[k * kM + size_t(a)] - kMin[a]) / (kMax[a] - kMin[a]);
      const double y = (u[k * kM + size_t(b)] - kMin[b]) / (kMax[b] - kMin[b]);
      sa += x, sb += y, saa += x * x, sbb += y * y, sab += x * y;
    }
    const double cov = sab / n - sa / n * sb / n;
    return cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
  };
  for (ExcitationSignal sig : {ExcitationSignal::Aprbs, ExcitationSignal::Steps, ExcitationSignal::Walk}) {
    const std::vector<float> own = run(sig, 4, false, 60000, 1.0f, 0.2f, 5.0f, false);
    const std::vector<float> mixed = run(sig, 4, false, 60000, 1.0f, 0.2f, 5.0f, true);
    for (int b = 1; b < kM; ++b) {
      EXPECT_LT(std::fabs(correlation(own, 0, b)), 0.2) << int(sig) << " inputs 0, " << b;
      EXPECT_GT(correlation(mixed, 0, b), 0.5) << int(sig) << " inputs 0, " << b;
    }
    // Not the joint signal: the inputs also move apart.
    size_t apart = 0;
    for (size_t k = 0; k < mixed.size() / kM; ++k)
      apart += std::fabs((mixed[k * kM + 1] - kMin[1]) / (kMax[1] - kMin[1]) - mixed[k * kM]) > 0.05f;
    EXPECT_GT(apart, mixed.size() / kM / 2) << int(sig);
  }
}

TEST(Excitation, BadParametersAreRefusedNamingTheField) {
  auto verdict = [](ExcitationSpec s) { return check_excitation(s, kRate); };
  ExcitationSpec ok;
  ok.duration = 10;
  EXPECT_EQ(verdict(ok).status, Status::Ok);
  ExcitationSpec s = ok;
  s.signal = ExcitationSignal(5);
  EXPECT_EQ(verdict(s).status, Status::OutOfRange);
  EXPECT_EQ(verdict(s).field, ExcitationField::Signal);
  s = ok, s.signal = ExcitationSignal::Aprbs, s.mixed = true;
  EXPECT_EQ(verdict(s).status, Status::Ok);
  s.joint = true;  // joint and mixed exclude each other
  EXPECT_EQ(verdict(s).status, Status::Inconsistent);
  EXPECT_EQ(verdict(s).field, ExcitationField::Options);
  s = ok, s.signal = ExcitationSignal::Prbs, s.mixed = true;  // +-1 leaves no spread
  EXPECT_EQ(verdict(s).status, Status::Inconsistent);
  EXPECT_EQ(verdict(s).field, ExcitationField::Options);
  s = ok, s.amplitude = NAN;
  EXPECT_EQ(verdict(s).status, Status::NotFinite);
  EXPECT_EQ(verdict(s).field, ExcitationField::Amplitude);
  s = ok, s.amplitude = 1.5f;
  EXPECT_EQ(verdict(s).status, Status::OutOfRange);
  s = ok, s.amplitude = 0.0f;
  EXPECT_EQ(verdict(s).status, Status::OutOfRange);
  s = ok, s.band_lo = 0.0f;
  EXPECT_EQ(verdict(s).field, ExcitationField::BandLo);
  s = ok, s.band_hi = INFINITY;
  EXPECT_EQ(verdict(s).status, Status::NotFinite);
  EXPECT_EQ(verdict(s).field, ExcitationField::BandHi);
  s = ok, s.band_hi = 51.0f;  // over Nyquist at 100 Hz
  EXPECT_EQ(verdict(s).status, Status::OutOfRange);
  s = ok, s.band_lo = 3.0f, s.band_hi = 2.0f;
  EXPECT_EQ(verdict(s).status, Status::Inconsistent);
  EXPECT_EQ(verdict(s).field, ExcitationField::BandHi);
  s = ok, s.duration = 0;
  EXPECT_EQ(verdict(s).field, ExcitationField::Duration);
  Excitation e;
  s = ok, s.amplitude = -1.0f;
  EXPECT_EQ(e.configure(s, kRate, kMin, kMax, kNeutral, kM).status, Status::OutOfRange);
}

}  // namespace
}  // namespace nlsoft
