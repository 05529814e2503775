// Reference paths y_ref(k), evaluated at control step k from a few parameters
// so the MCU can compute them on the fly (docs/platforms.md, "References"; the paper,
// section "Tendon-driven path following" and Figure "Swirl (HASEL)").
//
//   Infinity  y = { A sin^2(wk) + c0,  B sin(wk) cos(wk) + c1,  C sin(wk) + c2 }
//   Pringle   y1 = B cos(2 pi k / lambda) + c1,  y2 = C sin(2 pi k / lambda) + c2,
//             y0 = A ((y2 - c2)^2 / B^2 - (y1 - c1)^2 / C^2) + c0
//   Diagonal  phi = 2 pi k / lambda + 1e-6 k^2,
//             y1 = B sin(phi) + c1,  y2 = C sin(phi) + c2,  y0 as Pringle
//   Swirl     1130 points in mm, each held `hold` steps, y = c + scale * p:
//             30 at rest (0,0,0); 100 rising z 0 -> 0.5 (linspace, ends
//             included); 500 of the conical Archimedean spiral
//             theta = linspace(0, 4 pi, 500), p = (0.6 theta cos theta,
//             0.6 theta sin theta, 0.5 + 0.3 theta); the same 500 reversed.
//   Step      levels[0..level_count) each held `hold` steps, added to the
//             centre on every axis: y_i = c_i + levels[j] (the msd task of the
//             paper's Results is levels 0.5, 1, 2 m from c = 0).
//   Table     caller-owned points (count x n, row-major, absolute units), each
//             held `hold` steps; centre and scale do not apply.
//   Hold      y = c.
//
// Finite references (Swirl, Step, Table) hold their last point for every k
// past the end, so no k ever reads outside a buffer. For n < 3 the first n
// components are written (msd, n = 1, uses Step or the y0 of the others).
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "shared/remainder.hpp"
#include "shared/sincos.hpp"

namespace nlsoft {

enum class RefKind : uint8_t { Infinity, Pringle, Diagonal, Swirl, Step, Table, Hold };

constexpr int kRefKindCount = 7;
constexpr int kRefMaxDim = 3;
constexpr int kRefMaxLevels = 3;

// POD so a protocol message can carry it as is: 12 floats + 4 bytes.
struct RefParams {
  RefKind kind;
  uint8_t level_count;  // Step: how many of levels[] are used (0..3)
  uint16_t hold;        // Swirl, Table, Step: steps each point is held (0 acts as 1)
  float A, B, C;        // amplitudes: Infinity, Pringle, Diagonal
  float c[3];           // centre (offsets c0, c1, c2)
  float omega;          // Infinity: angle advanced per control step, rad
  float lambda;         // Pringle, Diagonal: period in control steps
  float scale;          // Swirl: amplitude scale
  float levels[kRefMaxLevels];  // Step: levels relative to the centre
};
static_assert(std::is_trivially_copyable<RefParams>::value && sizeof(RefParams) == 4 + 12 * 4,
              "RefParams is copied to and from the wire as is");

// Read-only view of an uploaded table of points (the owner keeps the buffer
// alive while the reference runs).
struct ReferenceTable {
  const float* points;  // count rows of n floats
  uint32_t count;
  uint8_t n;  // floats per point (1..3); missing axes read the centre
};

namespace swirl {
constexpr uint32_t kRestPoints = 30;
constexpr uint32_t kRisePoints = 100;
constexpr uint32_t kSpiralPoints = 500;
constexpr uint32_t kRiseStart = kRestPoints;                    // 30
constexpr uint32_t kSpiralStart = kRiseStart + kRisePoints;     // 130
constexpr uint32_t kReverseStart = kSpiralStart + kSpiralPoints;  // 630
constexpr uint32_t kPoints = kReverseStart + kSpiralPoints;     // 1130
constexpr float kRiseTop = 0.5f;     // mm
constexpr float kRadiusRate = 0.6f;  // mm per rad
constexpr float kZRate = 0.3f;       // mm per rad
constexpr float kThetaMax = 4.0f * 3.14159265358979323846f;
}  // namespace swirl

// The unscaled Swirl point `index` in mm (indices past the end give the last).
inline void swirl_point(uint32_t index, float p[3]) {
  using namespace swirl;
  if (index >= kPoints) index = kPoints - 1;
  p[0] = p[1] = p[2] = 0.0f;
  if (index < kRiseStart) return;
  if (index < kSpiralStart) {
    p[2] = kRiseTop * static_cast<float>(index - kRiseStart) /
           static_cast<float>(kRisePoints - 1);
    return;
  }
  const uint32_t i = index < kReverseStart ? index - kSpiralStart
                                           : kPoints - 1 - index;  // reverse run
  const float theta = kThetaMax * static_cast<float>(i) / static_cast<float>(kSpiralPoints - 1);
  const SinCos sc = sincos_fast(theta);
  p[0] = kRadiusRate * theta * sc.c;
  p[1] = kRadiusRate * theta * sc.s;
  p[2] = kRiseTop + kZRate * theta;
}

namespace detail {

constexpr float kTwoPi = 6.28318530717958647692f;

inline uint32_t hold_of(const RefParams& p) { return p.hold == 0 ? 1u : p.hold; }

inline uint32_t step_levels(const RefParams& p) {
  return p.level_count > kRefMaxLevels ? static_cast<uint32_t>(kRefMaxLevels) : p.level_count;
}

// 2 pi k / lambda with k reduced modulo lambda first: the remainder is exact, so the
// phase keeps full float precision however long the run (k < 2^24).
inline float periodic_phase(uint32_t k, float lambda) {
  if (!(lambda > 0.0f) || !std::isfinite(lambda)) return 0.0f;
  return kTwoPi * fmod_exact(static_cast<float>(k), lambda) / lambda;
}

// Pringle/Diagonal y0: a zero amplitude in a denominator drops that term
// instead of dividing by zero.
inline float saddle(float A, float B, float C, float d1, float d2) {
  const float t2 = B != 0.0f ? d2 * d2 / (B * B) : 0.0f;
  const float t1 = C != 0.0f ? d1 * d1 / (C * C) : 0.0f;
  return A * (t2 - t1);
}

}  // namespace detail

// Number of control steps of a finite reference; 0 means periodic or endless.
inline uint32_t reference_length(const RefParams& p, const ReferenceTable* table = nullptr) {
  const uint32_t hold = detail::hold_of(p);
  switch (p.kind) {
    case RefKind::Swirl: return swirl::kPoints * hold;
    case RefKind::Step: return detail::step_levels(p) * hold;
    case RefKind::Table:
      return (table != nullptr && table->points != nullptr) ? table->count * hold : 0u;
    default: return 0u;
  }
}

// y_ref(k) into y[0..n), n clamped to [0, 3].
inline void reference_at(const RefParams& p, const ReferenceTable* table, uint32_t k, float* y,
                         int n) {
  if (y == nullptr || n <= 0) return;
  if (n > kRefMaxDim) n = kRefMaxDim;
  float out[kRefMaxDim] = {p.c[0], p.c[1], p.c[2]};
  const uint32_t hold = detail::hold_of(p);
  switch (p.kind) {
    case RefKind::Infinity: {
      const SinCos sc = sincos_fast(p.omega * static_cast<float>(k));
      const float s = sc.s;
      const float co = sc.c;
      out[0] += p.A * s * s;
      out[1] += p.B * s * co;
      out[2] += p.C * s;
      break;
    }
    case RefKind::Pringle:
    case RefKind::Diagonal: {
      float d1, d2;
      if (p.kind == RefKind::Pringle) {
        const SinCos sc = sincos_fast(detail::periodic_phase(k, p.lambda));
        d1 = p.B * sc.c;
        d2 = p.C * sc.s;
      } else {
        const float kk = static_cast<float>(k) * 1e-3f;  // 1e-6 k^2 = (k / 1000)^2
        const float phi = detail::periodic_phase(k, p.lambda) + kk * kk;
        const float s = sincos_fast(phi).s;
        d1 = p.B * s;
        d2 = p.C * s;
      }
      out[0] += detail::saddle(p.A, p.B, p.C, d1, d2);
      out[1] += d1;
      out[2] += d2;
      break;
    }
    case RefKind::Swirl: {
      float q[3];
      swirl_point(k / hold, q);
      for (int i = 0; i < kRefMaxDim; ++i) out[i] += p.scale * q[i];
      break;
    }
    case RefKind::Step: {
      const uint32_t levels = detail::step_levels(p);
      if (levels == 0) break;
      uint32_t j = k / hold;
      if (j >= levels) j = levels - 1;
      for (int i = 0; i < kRefMaxDim; ++i) out[i] += p.levels[j];
      break;
    }
    case RefKind::Table: {
      if (table == nullptr || table->points == nullptr || table->count == 0 || table->n == 0) break;
      uint32_t j = k / hold;
      if (j >= table->count) j = table->count - 1;
      const int tn = table->n > kRefMaxDim ? kRefMaxDim : table->n;
      const float* row = table->points + static_cast<uint32_t>(table->n) * j;
      for (int i = 0; i < tn; ++i) out[i] = row[i];
      break;
    }
    case RefKind::Hold:
    default: break;
  }
  for (int i = 0; i < n; ++i) y[i] = out[i];
}

// Why a parameter set cannot be run, or nullptr when it can. Firmware checks
// this before accepting an upload so a bad set changes nothing.
inline const char* reference_check(const RefParams& p, const ReferenceTable* table = nullptr) {
  const float all[] = {p.A, p.B, p.C, p.c[0], p.c[1], p.c[2], p.omega, p.lambda, p.scale,
                       p.levels[0], p.levels[1], p.levels[2]};
  for (float v : all)
    if (!std::isfinite(v)) return "non-finite reference parameter";
  switch (p.kind) {
    case RefKind::Infinity: return nullptr;
    case RefKind::Pringle:
    case RefKind::Diagonal:
      if (!(p.lambda > 0.0f)) return "lambda must be > 0";
      if (p.A != 0.0f && (p.B == 0.0f || p.C == 0.0f)) return "B and C must be non-zero when A is";
      return nullptr;
    case RefKind::Swirl: return nullptr;
    case RefKind::Step:
      if (p.level_count == 0 || p.level_count > kRefMaxLevels) return "level_count must be 1..3";
      return nullptr;
    case RefKind::Table:
      if (table == nullptr || table->points == nullptr || table->count == 0) return "no table";
      if (table->n == 0 || table->n > kRefMaxDim) return "table point size must be 1..3";
      for (uint32_t i = 0; i < table->count * table->n; ++i)
        if (!std::isfinite(table->points[i])) return "non-finite table point";
      return nullptr;
    case RefKind::Hold: return nullptr;
  }
  return "unknown reference kind";
}

}  // namespace nlsoft
