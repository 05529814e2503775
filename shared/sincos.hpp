#pragma once
// sin and cos together, for the references the MCU computes every control
// step (reference.hpp). libm's sinf/cosf carry a Payne-Hanek reduction for
// arguments up to 1e38 (3.4 kB of flash and tables on the Cortex-M4F) and
// cost ~150 instructions each; the references' arguments are phases of at
// most a few thousand rad, where a three-part Cody-Waite reduction is exact.
// Absolute error below 2e-7 for |x| <= 6000 (tests/shared/test_reference.cpp
// measures it against double-precision std::sin/cos); beyond, x is first
// reduced modulo the float nearest 2 pi, which adds at most 3e-8 |x|: less
// than the rounding of a float phase that large (6e-8 |x|).
#include <cmath>
#include <cstdint>

#include "shared/remainder.hpp"

namespace nlsoft {

struct SinCos {
  float s, c;
};

inline SinCos sincos_fast(float x) {
  if (!(x - x == 0.0f)) return {x - x, x - x};  // NaN and infinities give NaN
  if (std::fabs(x) > 6000.0f) x = fmod_exact(x, 6.28318531f);
  // x = q pi/2 + r, |r| <= pi/4; pi/2 in three parts so q pi/2 is exact
  const float t = x * 0.636619772f;
  const int32_t q = int32_t(t + (t >= 0.0f ? 0.5f : -0.5f));
  const float fq = float(q);
  const float r = ((x - fq * 1.5703125f) - fq * 4.83751297e-4f) - fq * 7.54978995e-8f;
  const float r2 = r * r;
  // Taylor series to r^9 and r^10: truncation below 2e-9 on |r| <= pi/4
  const float s = r + r * r2 * (-1.0f / 6 + r2 * (1.0f / 120 + r2 * (-1.0f / 5040 + r2 * (1.0f / 362880))));
  const float c = 1.0f + r2 * (-0.5f + r2 * (1.0f / 24 + r2 * (-1.0f / 720 + r2 * (1.0f / 40320 + r2 * (-1.0f / 3628800)))));
  switch (q & 3) {
    case 0: return {s, c};
    case 1: return {c, -s};
    case 2: return {-s, -c};
    default: return {-c, s};
  }
}

}  // namespace nlsoft
