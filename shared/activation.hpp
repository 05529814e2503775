#pragma once
// Keras activations with their first and second derivatives, the three values
// forward-mode differentiation needs (see jet.hpp).
#include <cmath>
#include <cstdint>

namespace nlsoft {

enum class Activation : uint8_t { Linear = 0, Relu = 1, Tanh = 2, Sigmoid = 3, HardSigmoid = 4 };

inline bool activation_valid(uint8_t a) { return a <= static_cast<uint8_t>(Activation::HardSigmoid); }

struct ActValue {
  float f, df, d2f;
};

inline float activate(Activation a, float x) {
  switch (a) {
    case Activation::Relu: return x > 0.0f ? x : 0.0f;
    case Activation::Tanh: return std::tanh(x);
    case Activation::Sigmoid: return 1.0f / (1.0f + std::exp(-x));
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
      const float t = std::tanh(x);
      const float d = 1.0f - t * t;
      return {t, d, -2.0f * t * d};
    }
    case Activation::Sigmoid: {
      const float s = 1.0f / (1.0f + std::exp(-x));
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

}  // namespace nlsoft
