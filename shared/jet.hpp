#pragma once
// Forward-mode differentiation for the reference derivatives
// (derivatives.hpp): a Jet carries a value and its first derivatives along K
// input directions. The network code is written once over a scalar type
// (float or Jet), so the reference evaluates the same model as the value
// rollouts; the controller's own kernels (kernels.hpp, rollout.hpp) are held
// to it by tests.
//
// Only the first n directions are live (n = 0 for a constant), so copies and
// linear operations touch n floats, not the capacity's K. Operations write in
// place and may alias their inputs.
#include <cstdint>

#include "shared/activation.hpp"

namespace nlsoft {

template <int K>
struct Jet {
  static_assert(K >= 1 && K <= 255, "direction count is stored in a byte");
  float v = 0.0f;
  uint8_t n = 0;
  float d[K];

  Jet() = default;
  Jet(const Jet& o) { *this = o; }
  Jet& operator=(const Jet& o) {
    v = o.v;
    n = o.n;
    for (int a = 0; a < n; ++a) d[a] = o.d[a];
    return *this;
  }
};

// ---- scalar operations, overloaded for float and Jet -------------------------

inline float value_of(float x) { return x; }
template <int K>
inline float value_of(const Jet<K>& x) { return x.v; }

inline void set_constant(float& x, float c) { x = c; }
template <int K>
inline void set_constant(Jet<K>& x, float c) {
  x.v = c;
  x.n = 0;
}

// acc += (x * s - o) * w: a weight w applied to the input x normalised by
// scale s and offset o (s = 1, o = 0 past the first layer).
inline void mul_add(float& acc, float x, float w, float s = 1.0f, float o = 0.0f) { acc += (x * s - o) * w; }
template <int K>
inline void mul_add(Jet<K>& acc, const Jet<K>& x, float w, float s = 1.0f, float o = 0.0f) {
  acc.v += (x.v * s - o) * w;
  if (x.n == 0) return;
  for (int a = acc.n; a < x.n; ++a) acc.d[a] = 0.0f;  // a prefix grows in place
  if (acc.n < x.n) acc.n = x.n;
  const float sw = s * w;
  for (int a = 0; a < x.n; ++a) acc.d[a] += x.d[a] * sw;
}

// x = x * scale + offset
inline void affine(float& x, float scale, float offset) { x = x * scale + offset; }
template <int K>
inline void affine(Jet<K>& x, float scale, float offset) {
  x.v = x.v * scale + offset;
  for (int a = 0; a < x.n; ++a) x.d[a] *= scale;
}

inline void apply(Activation act, float& x) { x = activate(act, x); }
template <int K>
inline void apply(Activation act, Jet<K>& x) {
  if (x.n == 0) {
    x.v = activate(act, x.v);
    return;
  }
  const ActValue f = activate_d2(act, x.v);  // chain rule: (f o x)_a = f'(x) x_a
  x.v = f.f;
  for (int a = 0; a < x.n; ++a) x.d[a] *= f.df;
}

// out = x * y (element product of two variables, used by the GRU gates);
// out may alias x or y.
inline void multiply(float& out, float x, float y) { out = x * y; }
template <int K>
inline void multiply(Jet<K>& out, const Jet<K>& x, const Jet<K>& y) {
  const uint8_t n = x.n > y.n ? x.n : y.n;
  const float xv = x.v, yv = y.v;
  for (int a = 0; a < n; ++a) out.d[a] = (a < x.n ? x.d[a] : 0.0f) * yv + xv * (a < y.n ? y.d[a] : 0.0f);
  out.v = xv * yv;
  out.n = n;
}

}  // namespace nlsoft
