#pragma once
// Excitation signals for identification runs: open-loop inputs that drive a
// rig over its input range so a model can be learned from what it does.
// The firmware computes them each control step (protocol IDENT_START), so
// this is MCU code: no heap, no exceptions, float, fixed capacity, and the
// same seed gives the same sequence bit for bit on the host and the MCU
// for steps, prbs and aprbs (tests/firmware/test_m4_qemu.cpp); walk and
// chirp still differ there in the last bit now and then (their filter, expf
// and the sine's polynomial are left to each compiler and libm).
//
// Five signals, each a deviation d in [-1, 1] per input, mapped into the
// input's limits (below):
//   steps - a new uniform level after a uniform random hold of 1/band_hi to
//           1/band_lo seconds;
//   prbs  - a maximal-length binary sequence (Galois LFSR) of +-1, one bit
//           every 1/band_hi seconds, the register long enough that one
//           period lasts at least 1/band_lo seconds (a flat spectrum over
//           the band) and at least one bit per input. Every input runs the
//           same sequence, each shifted d bits after the one before it, d
//           the largest step below period/m that shares no factor with the
//           period (below);
//   aprbs - prbs's switching instants with a new uniform level at each
//           (amplitude-modulated PRBS, Nelles, Nonlinear System
//           Identification, ch. 19): the levels fill the range as steps'
//           do, the holds are the register's runs of equal bits;
//   walk  - a random walk reflected at +-1 that crosses the range in about
//           1/band_lo seconds, low-passed at band_hi (first order);
//   chirp - a sine whose frequency sweeps linearly from band_lo to band_hi
//           over the run's duration.
// Per input (each input its own stream, seeded from the seed and its index),
// jointly (every input the same deviation), or mixed: a shared stream c and
// each input's own o_i give d_i = c + (1 - |c|) o_i, so the inputs move
// together (the common mode a platform's height is) and apart around it;
// the spread narrows as c nears a limit, so every d_i stays in [-1, 1]
// without clamping (a clamp would pile samples on the limits) and c = +-1
// takes all inputs to the range's corner together. prbs has no mixed form:
// its c is always +-1, which leaves no spread (the joint signal).
//
// The amplitude a in (0, 1] is the fraction of an input's range the signal
// spans: a window a (u_max - u_min) wide centred on the neutral input and
// shifted inside [u_min, u_max] where the neutral sits near a limit (a rig
// whose neutral is u_min gets the lower part of its range, not half of it).
#include <cmath>
#include <cstdint>

#include "shared/rig_config.hpp"
#include "shared/fixed_math.hpp"
#include "shared/rng.hpp"
#include "shared/sincos.hpp"
#include "shared/status.hpp"

namespace nlsoft {

enum class ExcitationSignal : uint8_t { Steps = 0, Prbs = 1, Walk = 2, Chirp = 3, Aprbs = 4 };
constexpr uint8_t kExcitationSignalCount = 5;
// The signals' names as commands and rig files ([ident.steps]) write them,
// indexed by ExcitationSignal.
constexpr const char* kExcitationSignalNames[kExcitationSignalCount] = {"steps", "prbs", "walk", "chirp", "aprbs"};

struct ExcitationSpec {
  ExcitationSignal signal = ExcitationSignal::Prbs;
  bool joint = false;       // every input the same deviation
  bool mixed = false;       // a shared deviation plus each input's own (not with joint, nor prbs)
  uint32_t seed = 1;
  float amplitude = 0.8f;   // fraction of each input's range, (0, 1]
  float band_lo = 0.1f;     // Hz, > 0
  float band_hi = 2.0f;     // Hz, band_lo <= band_hi <= rate / 2
  uint32_t duration = 1;    // control steps, >= 1
};

// Which field a refusal names; the protocol's IDENT_START maps these to its
// field numbers.
enum class ExcitationField : uint8_t { Signal, Options, Amplitude, BandLo, BandHi, Duration, None };

struct ExcitationCheck {
  Status status;
  ExcitationField field;
};

// The rules, in field order; the first failure is reported.
inline ExcitationCheck check_excitation(const ExcitationSpec& s, float rate_hz) {
  using F = ExcitationField;
  if (uint8_t(s.signal) >= kExcitationSignalCount) return {Status::OutOfRange, F::Signal};
  if (s.mixed && (s.joint || s.signal == ExcitationSignal::Prbs)) return {Status::Inconsistent, F::Options};
  if (!std::isfinite(s.amplitude)) return {Status::NotFinite, F::Amplitude};
  if (!(s.amplitude > 0.0f && s.amplitude <= 1.0f)) return {Status::OutOfRange, F::Amplitude};
  if (!std::isfinite(s.band_lo)) return {Status::NotFinite, F::BandLo};
  if (!(s.band_lo > 0.0f)) return {Status::OutOfRange, F::BandLo};
  if (!std::isfinite(s.band_hi)) return {Status::NotFinite, F::BandHi};
  if (!(s.band_hi <= 0.5f * rate_hz)) return {Status::OutOfRange, F::BandHi};
  if (s.band_lo > s.band_hi) return {Status::Inconsistent, F::BandHi};
  if (s.duration == 0) return {Status::OutOfRange, F::Duration};
  return {Status::Ok, F::None};
}

// Feedback taps of maximal-length Galois LFSRs of 3..16 bits (period
// 2^bits - 1); tests/shared/test_excitation.cpp checks every period.
inline uint32_t prbs_taps(int bits) {
  static const uint16_t taps[] = {0x6,   0xC,   0x14,  0x30,   0x60,   0xB8,   0x110,
                                  0x240, 0x500, 0x829, 0x100D, 0x2015, 0x6000, 0xD008};
  if (bits < 3) bits = 3;
  if (bits > 16) bits = 16;
  return taps[bits - 3];
}

class Excitation {
 public:
  // Fails with check_excitation's verdict (nothing changes then), or
  // TooLarge for more inputs than kRigMaxM.
  ExcitationCheck configure(const ExcitationSpec& spec, float rate_hz, const float* u_min, const float* u_max,
                            const float* u_neutral, int m) {
    if (m < 1 || m > kRigMaxM || !(rate_hz > 0.0f)) return {Status::TooLarge, ExcitationField::None};
    const ExcitationCheck c = check_excitation(spec, rate_hz);
    if (c.status != Status::Ok) return c;
    spec_ = spec;
    rate_ = rate_hz;
    m_ = m;
    k_ = 0;
    for (int i = 0; i < m; ++i) {
      float span = spec.amplitude * (u_max[i] - u_min[i]);
      float lo = u_neutral[i] - 0.5f * span;
      if (lo < u_min[i]) lo = u_min[i];
      if (lo + span > u_max[i]) lo = u_max[i] - span;
      lo_[i] = lo;
      span_[i] = span;
      min_[i] = u_min[i];
      max_[i] = u_max[i];
    }
    hold_min_ = steps_of(1.0f / spec.band_hi);
    hold_max_ = steps_of(1.0f / spec.band_lo);
    // The register whose period (2^bits - 1 bits of hold_min_ steps) covers 1/band_lo.
    bits_ = 3;
    while (bits_ < 16 && float((1u << bits_) - 1u) * float(hold_min_) < rate_hz / spec.band_lo) ++bits_;
    walk_sigma_ = std::sqrt(spec.band_lo / rate_hz);
    const float a = 6.28318531f * spec.band_hi / rate_hz;
    smooth_ = a > 10.0f ? 1.0f : 1.0f - fixed_math::exp(-a);
    const int channels = spec.joint ? 1 : m;
    if (bits_ < channels) bits_ = channels;
    for (int i = 0; i < channels; ++i) start(ch_[i], spec.seed, i);
    spread_registers(channels);
    // The shared stream's index is past every input's, so mixing leaves
    // each input's own stream as it is without it.
    if (spec.mixed) start(ch_[kShared], spec.seed, kShared);
    return {Status::Ok, ExcitationField::None};
  }

  // The next step's inputs, m of them, each inside [u_min, u_max].
  void next(float* u) {
    float d[kRigMaxM];
    const int channels = spec_.joint ? 1 : m_;
    for (int i = 0; i < channels; ++i) d[i] = advance(ch_[i]);
    for (int i = channels; i < m_; ++i) d[i] = d[0];
    if (spec_.mixed) {
      const float c = advance(ch_[kShared]);
      const float spread = 1.0f - std::fabs(c);
      for (int i = 0; i < m_; ++i) d[i] = std::fma(spread, d[i], c);
    }
    for (int i = 0; i < m_; ++i) {
      // Each a + b c here is one fused multiply-add, written out: the
      // Cortex-M4F's compiler fuses it by itself (VFMA) where x86-64's does
      // not, and left to them the host and the board differ in the last bit.
      float v = std::fma(0.5f * (d[i] + 1.0f), span_[i], lo_[i]);
      v = v < min_[i] ? min_[i] : (v > max_[i] ? max_[i] : v);
      u[i] = v;
    }
    ++k_;
  }

  uint32_t steps_done() const { return k_; }
  bool done() const { return k_ >= spec_.duration; }
  // The chirp's frequency at step k (Hz): band_lo at the start, band_hi at the end.
  float chirp_hz(uint32_t k) const {
    return spec_.band_lo + (spec_.band_hi - spec_.band_lo) * float(k) / float(spec_.duration);
  }
  int prbs_bits() const { return bits_; }

 private:
  // A walk's step: zero mean, unit variance (the sum of four uniforms,
  // centred and scaled: Irwin-Hall), so no logf/sinf/cosf is linked into
  // an image for it (Box-Muller's pull in ~3.8 kB of libm on the M4F).
  static float bell(Rng& rng) {
    const float sum = rng.uniform() + rng.uniform() + rng.uniform() + rng.uniform();
    return (sum - 2.0f) * 1.7320508f;
  }

  struct Channel {
    Rng rng;
    uint32_t left = 0;  // steps before the next level or bit
    uint32_t lfsr = 1;
    uint32_t bit = 2;  // the last bit; none at the start, so aprbs draws its first level
    float level = 0.0f, walk = 0.0f, smooth = 0.0f, phase = 0.0f;
  };

  uint32_t steps_of(float seconds) const {
    const float s = seconds * rate_ + 0.5f;
    if (!(s >= 1.0f)) return 1;
    return s > 4.0e9f ? 4000000000u : uint32_t(s);
  }

  void start(Channel& c, uint32_t seed, int index) {
    // Each input's stream from the seed and its index: seed 0 input 1 is
    // not seed 1 input 0.
    c.rng.reseed(seed ^ (0x9E3779B9u * uint32_t(index + 1)));
    c.left = 0;
    const uint32_t mask = (1u << bits_) - 1u;
    c.lfsr = c.rng.next_u32() & mask;
    if (c.lfsr == 0) c.lfsr = 1;
    c.bit = 2;
    c.level = 0.0f;
    c.walk = c.rng.uniform(-1.0f, 1.0f);
    c.smooth = c.walk;
    c.phase = spec_.signal == ExcitationSignal::Chirp && !spec_.joint ? c.rng.uniform(0.0f, 6.28318531f) : 0.0f;
  }

  // Why the inputs share one sequence, shifted: registers started at
  // random states of one sequence are random shifts of it, and two inputs
  // landed on the same shift often (6 inputs on a 63-bit period: one seed
  // in five), driving them identically; an input could also be the product
  // (the bitwise XOR) of others, which a model cannot tell from its own
  // effect. Input i's bit is a linear form of input 0's register over
  // GF(2), alpha^(i d) in the register's field: with d prime to the period,
  // alpha^d generates the field, so the forms for i < m <= bits are
  // independent and every m-bit pattern of the inputs occurs
  // (tests/shared/test_excitation.cpp checks each register and m). Input
  // 0 keeps its seeded start. At most one period of register steps in all,
  // once per run (65 535 for 16 bits: ~0.3 M instructions on the M4F).
  void spread_registers(int channels) {
    const uint32_t period = (1u << bits_) - 1u;
    const uint32_t taps = prbs_taps(bits_);
    uint32_t d = period / uint32_t(channels);
    while (d > 1 && gcd(d, period) != 1u) --d;
    for (int i = 1; i < channels; ++i) {
      uint32_t s = ch_[i - 1].lfsr;
      for (uint32_t k = 0; k < d; ++k) s = (s >> 1) ^ ((s & 1u) ? taps : 0u);
      ch_[i].lfsr = s;
    }
  }

  static uint32_t gcd(uint32_t a, uint32_t b) {
    while (b != 0) {
      const uint32_t t = a % b;
      a = b;
      b = t;
    }
    return a;
  }

  float advance(Channel& c) {
    switch (spec_.signal) {
      case ExcitationSignal::Steps:
        if (c.left == 0) {
          c.level = c.rng.uniform(-1.0f, 1.0f);
          const uint32_t spread = hold_max_ - hold_min_ + 1u;
          c.left = hold_min_ + (spread ? c.rng.next_u32() % spread : 0u);
        }
        --c.left;
        return c.level;
      case ExcitationSignal::Prbs:
      case ExcitationSignal::Aprbs:
        if (c.left == 0) {
          const uint32_t bit = c.lfsr & 1u;
          c.lfsr >>= 1;
          if (bit) c.lfsr ^= prbs_taps(bits_);
          // aprbs: a new level where the bit changes. Its holds are the
          // register's runs, not steps' uniform 1/band_hi..1/band_lo: half
          // of them one bit long, a quarter two..., the longest `bits_`, so
          // the level changes about band_hi/2 times a second with a flat
          // spectrum up to band_hi (steps' mean hold, near 1/(2 band_lo),
          // spends most of a run settled and gives a tenth the levels).
          if (spec_.signal == ExcitationSignal::Prbs)
            c.level = bit ? 1.0f : -1.0f;
          else if (bit != c.bit)
            c.level = c.rng.uniform(-1.0f, 1.0f);
          c.bit = bit;
          c.left = hold_min_;
        }
        --c.left;
        return c.level;
      case ExcitationSignal::Walk: {
        float x = c.walk + walk_sigma_ * bell(c.rng);
        if (x > 1.0f) x = 2.0f - x;  // reflected at the ends
        if (x < -1.0f) x = -2.0f - x;
        c.walk = x < -1.0f ? -1.0f : (x > 1.0f ? 1.0f : x);
        c.smooth += smooth_ * (c.walk - c.smooth);
        return c.smooth;
      }
      case ExcitationSignal::Chirp: {
        const float s = sincos_fast(c.phase).s;
        // The phase kept in [0, 2 pi): a float phase summed over 10 minutes
        // at 1 kHz would lose the sweep's resolution.
        c.phase += 6.28318531f * chirp_hz(k_) / rate_;
        if (c.phase >= 6.28318531f) c.phase -= 6.28318531f;
        return s;
      }
    }
    return 0.0f;
  }

  ExcitationSpec spec_{};
  float rate_ = 1.0f;
  int m_ = 0;
  uint32_t k_ = 0;
  uint32_t hold_min_ = 1, hold_max_ = 1;
  int bits_ = 3;
  float walk_sigma_ = 0.0f, smooth_ = 1.0f;
  float lo_[kRigMaxM] = {}, span_[kRigMaxM] = {}, min_[kRigMaxM] = {}, max_[kRigMaxM] = {};
  static constexpr int kShared = kRigMaxM;  // mixed's shared stream
  Channel ch_[kRigMaxM + 1];
};

}  // namespace nlsoft
