// Seeded noise source for the simulated plants: the same seed gives the same
// run, bit for bit, on the host and on the MCU (only 32-bit integer ops and
// float maths, no global state).
//
// Generator: xoshiro128** (Blackman & Vigna, "Scrambled linear pseudorandom
// number generators", 2018), 128-bit state, period 2^128 - 1. The state is
// filled from the 32-bit seed by SplitMix32 so that nearby seeds (0, 1, 2...)
// give unrelated streams and the state is never all zero.
#pragma once

#include <cmath>
#include <cstdint>

#include "shared/fixed_math.hpp"

namespace nlsoft {

class Rng {
 public:
  explicit Rng(uint32_t seed = 0) { reseed(seed); }

  void reseed(uint32_t seed) {
    uint32_t x = seed;
    for (uint32_t& word : s_) word = splitmix32(x);
    if ((s_[0] | s_[1] | s_[2] | s_[3]) == 0u) s_[0] = 1u;  // the one forbidden state
    has_spare_ = false;
    spare_ = 0.0f;
  }

  uint32_t next_u32() {
    const uint32_t result = rotl(s_[1] * 5u, 7) * 9u;
    const uint32_t t = s_[1] << 9;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 11);
    return result;
  }

  // Uniform in [0, 1): the top 24 bits fill a float mantissa exactly, so every
  // value is representable and 1.0f is never returned.
  float uniform() { return static_cast<float>(next_u32() >> 8) * kInv24; }

  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }

  // Standard normal by Box-Muller; the second variate of each pair is kept for
  // the next call. u1 lies in (0, 1] so log(u1) is finite.
  float gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const float u1 = static_cast<float>((next_u32() >> 8) + 1u) * kInv24;
    const float u2 = uniform();
    const float radius = std::sqrt(-2.0f * fixed_math::log(u1));
    const float angle = kTwoPi * u2;
    spare_ = radius * fixed_math::sin(angle);
    has_spare_ = true;
    return radius * fixed_math::cos(angle);
  }

  float gaussian(float mean, float sigma) { return mean + sigma * gaussian(); }

 private:
  static constexpr float kInv24 = 1.0f / 16777216.0f;
  static constexpr float kTwoPi = 6.28318530717958647692f;

  static uint32_t rotl(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

  // SplitMix32 (the 32-bit variant of Steele et al.'s SplitMix with the
  // "lowbias32" finaliser by C. Wellons).
  static uint32_t splitmix32(uint32_t& x) {
    x += 0x9E3779B9u;
    uint32_t z = x;
    z = (z ^ (z >> 16)) * 0x21F0AAADu;
    z = (z ^ (z >> 15)) * 0x735A2D97u;
    return z ^ (z >> 15);
  }

  uint32_t s_[4]{};
  float spare_ = 0.0f;
  bool has_spare_ = false;
};

}  // namespace nlsoft
