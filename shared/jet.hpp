#pragma once
// Forward-mode differentiation for the `exact` derivative mode.
//
// A Jet carries a value, its first derivatives along K input directions and
// the second derivatives along each of those directions (the diagonal of the
// Hessian). That is exactly what the paper's cost needs: the Jacobian
// dy/dU (eq. first_derivative_full) and the per-direction curvature
// d2y/dU2 (eq. first_derivative_full2), here through the whole recursive
// horizon instead of holding X_j = X. The network code is written once over a
// scalar type (float or Jet), so `fd` and `exact` evaluate the same model.
//
#include "shared/activation.hpp"

namespace nlsoft {

template <int K>
struct Jet {
  static_assert(K >= 1 && K <= 255, "direction count is stored in a byte");
  float v = 0.0f;
  float d[K] = {};
  float dd[K] = {};
  // Directions in use: 0 for a constant, otherwise the count of seeded
  // directions (d[a], dd[a] for a >= n are stale and never read). Loops run to
  // n, not K, so a capacity sized for the largest platform costs nothing on
  // a small one, and multiply-adds by constants (sensor channels, old
  // history) cost one float operation.
  uint8_t n = 0;
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

namespace detail {
// Zero-extends acc's derivatives to n directions.
template <int K>
inline void widen(Jet<K>& acc, uint8_t n) {
  for (int a = acc.n; a < n; ++a) acc.d[a] = acc.dd[a] = 0.0f;
  acc.n = n;
}
}  // namespace detail

// acc += x * w, w a constant weight
inline void mul_add(float& acc, float x, float w) { acc += x * w; }
template <int K>
inline void mul_add(Jet<K>& acc, const Jet<K>& x, float w) {
  acc.v += x.v * w;
  if (x.n == 0) return;
  if (acc.n < x.n) detail::widen(acc, x.n);
  for (int a = 0; a < x.n; ++a) {
    acc.d[a] += x.d[a] * w;
    acc.dd[a] += x.dd[a] * w;
  }
}

// x = x * scale + offset
inline void affine(float& x, float scale, float offset) { x = x * scale + offset; }
template <int K>
inline void affine(Jet<K>& x, float scale, float offset) {
  x.v = x.v * scale + offset;
  for (int a = 0; a < x.n; ++a) {
    x.d[a] *= scale;
    x.dd[a] *= scale;
  }
}

inline void apply(Activation act, float& x) { x = activate(act, x); }
template <int K>
inline void apply(Activation act, Jet<K>& x) {
  if (x.n == 0) {
    x.v = activate(act, x.v);
    return;
  }
  const ActValue f = activate_d2(act, x.v);
  x.v = f.f;
  // chain rule along one direction: (f o x)'' = f''(x) x'^2 + f'(x) x''
  for (int a = 0; a < x.n; ++a) {
    x.dd[a] = f.d2f * x.d[a] * x.d[a] + f.df * x.dd[a];
    x.d[a] = f.df * x.d[a];
  }
}

// out = x * y (element product of two variables, used by the GRU gates)
inline void multiply(float& out, float x, float y) { out = x * y; }
template <int K>
inline void multiply(Jet<K>& out, const Jet<K>& x, const Jet<K>& y) {
  Jet<K> r;
  r.v = x.v * y.v;
  r.n = x.n > y.n ? x.n : y.n;
  for (int a = 0; a < r.n; ++a) {
    const float xd = a < x.n ? x.d[a] : 0.0f, xdd = a < x.n ? x.dd[a] : 0.0f;
    const float yd = a < y.n ? y.d[a] : 0.0f, ydd = a < y.n ? y.dd[a] : 0.0f;
    r.d[a] = xd * y.v + x.v * yd;
    r.dd[a] = xdd * y.v + 2.0f * xd * yd + x.v * ydd;
  }
  out = r;
}

// out = x + y
inline void add(float& out, float x, float y) { out = x + y; }
template <int K>
inline void add(Jet<K>& out, const Jet<K>& x, const Jet<K>& y) {
  Jet<K> r;
  r.v = x.v + y.v;
  r.n = x.n > y.n ? x.n : y.n;
  for (int a = 0; a < r.n; ++a)
    r.d[a] = (a < x.n ? x.d[a] : 0.0f) + (a < y.n ? y.d[a] : 0.0f),
    r.dd[a] = (a < x.n ? x.dd[a] : 0.0f) + (a < y.n ? y.dd[a] : 0.0f);
  out = r;
}

}  // namespace nlsoft
