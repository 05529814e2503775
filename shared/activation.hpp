#pragma once
// Keras activations: exact (fixed_math.hpp: the same bits on every x86-64
// CPU; newlib's on the MCU) with first and second
// derivatives for the model pipeline and the reference derivatives (jet.hpp),
// and fast with the first derivative for the controller's kernels
// (rollout.hpp), where a libm call costs more than a whole layer on an MCU.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "shared/fixed_math.hpp"

namespace nlsoft {

enum class Activation : uint8_t { Linear = 0, Relu = 1, Tanh = 2, Sigmoid = 3, HardSigmoid = 4 };

inline bool activation_valid(uint8_t a) { return a <= static_cast<uint8_t>(Activation::HardSigmoid); }

// Keras' name of an activation, as model files, rig files and messages spell it.
constexpr const char* activation_name(Activation a) {
  switch (a) {
    case Activation::Relu: return "relu";
    case Activation::Tanh: return "tanh";
    case Activation::Sigmoid: return "sigmoid";
    case Activation::HardSigmoid: return "hard_sigmoid";
    case Activation::Linear: return "linear";
  }
  return "?";
}

struct ActValue {
  float f, df, d2f;
};

inline float activate(Activation a, float x) {
  switch (a) {
    case Activation::Relu: return x > 0.0f ? x : 0.0f;
    case Activation::Tanh: return fixed_math::tanh(x);
    case Activation::Sigmoid: return 1.0f / (1.0f + fixed_math::exp(-x));
    // Keras 2.x: clip(0.2 x + 0.5, 0, 1)
    case Activation::HardSigmoid: {
      const float y = 0.2f * x + 0.5f;
      return y < 0.0f ? 0.0f : (y > 1.0f ? 1.0f : y);
    }
    case Activation::Linear:
    default: return x;
  }
}

// Piecewise-linear activations have d2f = 0 almost everywhere; at the kinks we
// take the right-hand derivative, as a finite-difference stencil would see it.
inline ActValue activate_d2(Activation a, float x) {
  switch (a) {
    case Activation::Relu: return x > 0.0f ? ActValue{x, 1.0f, 0.0f} : ActValue{0.0f, 0.0f, 0.0f};
    case Activation::Tanh: {
      const float t = fixed_math::tanh(x);
      const float d = 1.0f - t * t;
      return {t, d, -2.0f * t * d};
    }
    case Activation::Sigmoid: {
      const float s = 1.0f / (1.0f + fixed_math::exp(-x));
      const float d = s * (1.0f - s);
      return {s, d, d * (1.0f - 2.0f * s)};
    }
    case Activation::HardSigmoid: {
      const float y = 0.2f * x + 0.5f;
      if (y <= 0.0f) return {0.0f, 0.0f, 0.0f};
      if (y >= 1.0f) return {1.0f, 0.0f, 0.0f};
      return {y, 0.2f, 0.0f};
    }
    case Activation::Linear:
    default: return {x, 1.0f, 0.0f};
  }
}

// e^x without libm, relative error below 2.5e-7 over the float range
// (tests/shared/test_activation.cpp measures it against std::exp): x = i ln2
// + f with i = round(x / ln2) and |f| <= ln2 / 2 (Cody-Waite: ln2 split in
// two so f is exact), e^f by its Taylor series to degree 6 (truncation
// below 1.2e-7), 2^i put straight into the exponent bits. Inputs are clamped
// to [-87, 88], where e^x is a normal float; NaN gives e^88.
// round(x / ln2) by adding 1.5 * 2^23, whose float spacing is 1: the sum's
// low mantissa bits hold the rounded integer, two adds and a move instead of
// a sign test and two conversions (a fifth of the function on the M4F, and
// the GRU's gates call it 15 times per horizon step).
inline float fast_exp(float x) {
  x = x < 88.0f ? x : 88.0f;
  x = x > -87.0f ? x : -87.0f;
  const float t = x * 1.44269504f;
  constexpr float kRound = 12582912.0f;  // 1.5 * 2^23, bits 0x4b400000
  const float shifted = t + kRound;
  const float fi = shifted - kRound;
  uint32_t sbits;
  std::memcpy(&sbits, &shifted, sizeof sbits);
  const int i = int(sbits) - 0x4b400000;
  const float f = (x - fi * 0.693145752f) - fi * 1.42860677e-6f;
  float p = 1.0f / 720.0f;
  p = p * f + 1.0f / 120.0f;
  p = p * f + 1.0f / 24.0f;
  p = p * f + 1.0f / 6.0f;
  p = p * f + 0.5f;
  p = p * f + 1.0f;
  p = p * f + 1.0f;
  const uint32_t bits = uint32_t(i + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

namespace detail {
// 2^(i/16), i = 0..15, each the float nearest to it.
inline constexpr float kExp2Sixteenths[16] = {
    0x1.000000p+0f, 0x1.0b5586p+0f, 0x1.172b84p+0f, 0x1.2387a6p+0f, 0x1.306fe0p+0f, 0x1.3dea64p+0f,
    0x1.4bfdaep+0f, 0x1.5ab07ep+0f, 0x1.6a09e6p+0f, 0x1.7a1148p+0f, 0x1.8ace54p+0f, 0x1.9c4918p+0f,
    0x1.ae89fap+0f, 0x1.c199bep+0f, 0x1.d5818ep+0f, 0x1.ea4afap+0f};

// e^y for 0 <= y < 18 only (tanh's range below): y = (16 i + s) ln2 / 16
// + f with |f| <= ln2 / 32, e^y = 2^i 2^(s/16) e^f; 2^(s/16) from the
// table, e^f by its Taylor series to degree 3 (truncation below 1e-8).
// Half fast_exp's instructions: no clamp, a cubic instead of a degree-6
// polynomial, for 64 bytes of table.
inline float exp_0_18(float y) {
  constexpr float kRound = 12582912.0f;  // 1.5 * 2^23: see fast_exp
  const float shifted = y * 23.0831203f + kRound;  // y 16 / ln2
  const float fi = shifted - kRound;
  uint32_t sbits;
  std::memcpy(&sbits, &shifted, sizeof sbits);
  const uint32_t n = sbits - 0x4b400000u;  // >= 0: y >= 0
  // ln2 / 16 in two parts, the first with 12 significant bits so fi times it is exact (fi < 512)
  const float f = (y - fi * 0.0433197021484375f) - fi * 1.99663646e-6f;
  const float p = 1.0f + f * (1.0f + f * (0.5f + f * (1.0f / 6.0f)));
  uint32_t bits;
  std::memcpy(&bits, &kExp2Sixteenths[n & 15u], sizeof bits);
  bits += (n >> 4) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}
}  // namespace detail

// tanh(x) = 1 - 2 / (e^{2|x|} + 1) with the sign of x: absolute error below
// 3e-7 (tests/shared/test_activation.cpp); exactly +-1 past |x| = 9.
inline float fast_tanh(float x) {
  const float ax = std::fabs(x);
  const float t = ax < 9.0f ? 1.0f - 2.0f / (detail::exp_0_18(2.0f * ax) + 1.0f) : 1.0f;
  return x < 0.0f ? -t : t;
}

inline float fast_sigmoid(float x) { return 1.0f / (1.0f + fast_exp(-x)); }

// An activation's value and slope at x, the two numbers the controller's
// forward-mode Jacobian needs (the chain rule's f'(z)).
struct ActSlope {
  float f, df;
};

inline ActSlope activate_slope(Activation a, float x) {
  switch (a) {
    case Activation::Relu: return x > 0.0f ? ActSlope{x, 1.0f} : ActSlope{0.0f, 0.0f};
    case Activation::Tanh: {
      const float t = fast_tanh(x);
      return {t, 1.0f - t * t};
    }
    case Activation::Sigmoid: {
      const float s = fast_sigmoid(x);
      return {s, s * (1.0f - s)};
    }
    case Activation::HardSigmoid: {
      const float y = 0.2f * x + 0.5f;
      if (y <= 0.0f) return {0.0f, 0.0f};
      if (y >= 1.0f) return {1.0f, 0.0f};
      return {y, 0.2f};
    }
    case Activation::Linear:
    default: return {x, 1.0f};
  }
}

// f and f' over a whole layer: the switch runs once per layer, not per unit.
inline void activate_slopes(Activation a, float* z, float* df, int count) {
  switch (a) {
    case Activation::Relu:
      for (int j = 0; j < count; ++j) {
        df[j] = z[j] > 0.0f ? 1.0f : 0.0f;
        z[j] = z[j] > 0.0f ? z[j] : 0.0f;
      }
      return;
    case Activation::Linear:
      for (int j = 0; j < count; ++j) df[j] = 1.0f;
      return;
    default:
      for (int j = 0; j < count; ++j) {
        const ActSlope f = activate_slope(a, z[j]);
        z[j] = f.f;
        df[j] = f.df;
      }
  }
}

}  // namespace nlsoft
