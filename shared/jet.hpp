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
// `active` marks a Jet whose derivatives are all zero so multiply-adds by
// constant inputs (sensor channels, old history) cost one float operation.
#include "shared/activation.hpp"

namespace nlsoft {

template <int K>
struct Jet {
  float v = 0.0f;
  float d[K] = {};
  float dd[K] = {};
  bool active = false;
};

// ---- scalar operations, overloaded for float and Jet -------------------------

inline float value_of(float x) { return x; }
template <int K>
inline float value_of(const Jet<K>& x) { return x.v; }

inline void set_constant(float& x, float c) { x = c; }
template <int K>
inline void set_constant(Jet<K>& x, float c) {
  x.v = c;
  if (x.active) {
    for (int a = 0; a < K; ++a) x.d[a] = x.dd[a] = 0.0f;
    x.active = false;
  }
}

// acc += x * w, w a constant weight
inline void mul_add(float& acc, float x, float w) { acc += x * w; }
template <int K>
inline void mul_add(Jet<K>& acc, const Jet<K>& x, float w) {
  acc.v += x.v * w;
  if (!x.active) return;
  if (!acc.active) {
    for (int a = 0; a < K; ++a) acc.d[a] = acc.dd[a] = 0.0f;
    acc.active = true;
  }
  for (int a = 0; a < K; ++a) {
    acc.d[a] += x.d[a] * w;
    acc.dd[a] += x.dd[a] * w;
  }
}

// x = x * scale + offset
inline void affine(float& x, float scale, float offset) { x = x * scale + offset; }
template <int K>
inline void affine(Jet<K>& x, float scale, float offset) {
  x.v = x.v * scale + offset;
  if (!x.active) return;
  for (int a = 0; a < K; ++a) {
    x.d[a] *= scale;
    x.dd[a] *= scale;
  }
}

inline void apply(Activation act, float& x) { x = activate(act, x); }
template <int K>
inline void apply(Activation act, Jet<K>& x) {
  if (!x.active) {
    x.v = activate(act, x.v);
    return;
  }
  const ActValue f = activate_d2(act, x.v);
  x.v = f.f;
  // chain rule along one direction: (f o x)'' = f''(x) x'^2 + f'(x) x''
  for (int a = 0; a < K; ++a) {
    x.dd[a] = f.d2f * x.d[a] * x.d[a] + f.df * x.dd[a];
    x.d[a] = f.df * x.d[a];
  }
}

// out = x * y (element product of two variables, used by the GRU gates)
inline void multiply(float& out, float x, float y) { out = x * y; }
template <int K>
inline void multiply(Jet<K>& out, const Jet<K>& x, const Jet<K>& y) {
  const bool act = x.active || y.active;
  Jet<K> r;
  r.v = x.v * y.v;
  r.active = act;
  if (act) {
    for (int a = 0; a < K; ++a) {
      const float xd = x.active ? x.d[a] : 0.0f, xdd = x.active ? x.dd[a] : 0.0f;
      const float yd = y.active ? y.d[a] : 0.0f, ydd = y.active ? y.dd[a] : 0.0f;
      r.d[a] = xd * y.v + x.v * yd;
      r.dd[a] = xdd * y.v + 2.0f * xd * yd + x.v * ydd;
    }
  }
  out = r;
}

// out = x + y
inline void add(float& out, float x, float y) { out = x + y; }
template <int K>
inline void add(Jet<K>& out, const Jet<K>& x, const Jet<K>& y) {
  Jet<K> r;
  r.v = x.v + y.v;
  r.active = x.active || y.active;
  if (r.active) {
    for (int a = 0; a < K; ++a) {
      r.d[a] = (x.active ? x.d[a] : 0.0f) + (y.active ? y.d[a] : 0.0f);
      r.dd[a] = (x.active ? x.dd[a] : 0.0f) + (y.active ? y.dd[a] : 0.0f);
    }
  }
  out = r;
}

}  // namespace nlsoft
