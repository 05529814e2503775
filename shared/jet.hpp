#pragma once
// Forward-mode differentiation for the `exact` derivative mode.
//
// A Jet carries a value, its first derivatives along K input directions and,
// when Second is set, all its second derivatives (the triangle of the K x K
// Hessian). That is what the cost's full Hessian (eq. cost2) needs: the
// Jacobian dy/dU and the curvature d2y/dU2 of every prediction, through the
// whole recursive horizon instead of the paper's X_j = X shortcut. Without
// Second the solver uses the Gauss-Newton Hessian: a capacity chooses (see
// capacity.hpp). The network code is written once over a scalar type (float
// or Jet), so `fd` and `exact` evaluate the same model.
//
// Only the first n directions are live (n = 0 for a constant), and the
// triangle is stored column by column, pair (a <= b) at b(b+1)/2 + a, so the
// live part is always a prefix: copies and linear operations touch n + n(n+1)/2
// floats, not the capacity's K + K(K+1)/2. Operations write in place and may
// alias their inputs.
#include <cstdint>

#include "shared/activation.hpp"

namespace nlsoft {

template <int K, bool Second = true>
struct Jet {
  static_assert(K >= 1 && K <= 255, "direction count is stored in a byte");
  static constexpr bool kSecond = Second;
  static constexpr int kPairs = Second ? K * (K + 1) / 2 : 1;
  static constexpr int pair(int a, int b) { return b * (b + 1) / 2 + a; }  // a <= b
  static constexpr int pairs(int n) { return Second ? n * (n + 1) / 2 : 0; }

  float v = 0.0f;
  uint8_t n = 0;
  float d[K];
  float dd[kPairs];

  Jet() = default;
  Jet(const Jet& o) { *this = o; }
  Jet& operator=(const Jet& o) {
    v = o.v;
    n = o.n;
    for (int a = 0; a < n; ++a) d[a] = o.d[a];
    for (int i = 0; i < pairs(n); ++i) dd[i] = o.dd[i];
    return *this;
  }
};

// ---- scalar operations, overloaded for float and Jet -------------------------

inline float value_of(float x) { return x; }
template <int K, bool S>
inline float value_of(const Jet<K, S>& x) { return x.v; }

inline void set_constant(float& x, float c) { x = c; }
template <int K, bool S>
inline void set_constant(Jet<K, S>& x, float c) {
  x.v = c;
  x.n = 0;
}

namespace detail {
// Zero-extends x's derivatives to n directions (a prefix grows in place).
template <int K, bool S>
inline void widen(Jet<K, S>& x, uint8_t n) {
  for (int a = x.n; a < n; ++a) x.d[a] = 0.0f;
  for (int i = Jet<K, S>::pairs(x.n); i < Jet<K, S>::pairs(n); ++i) x.dd[i] = 0.0f;
  x.n = n;
}
}  // namespace detail

// acc += (x * s - o) * w: a weight w applied to the input x normalised by
// scale s and offset o (s = 1, o = 0 past the first layer).
inline void mul_add(float& acc, float x, float w, float s = 1.0f, float o = 0.0f) { acc += (x * s - o) * w; }
template <int K, bool S>
inline void mul_add(Jet<K, S>& acc, const Jet<K, S>& x, float w, float s = 1.0f, float o = 0.0f) {
  acc.v += (x.v * s - o) * w;
  if (x.n == 0) return;
  if (acc.n < x.n) detail::widen(acc, x.n);
  const float sw = s * w;
  if (x.n == K) {  // the common case: every direction live, fixed trip counts
    for (int a = 0; a < K; ++a) acc.d[a] += x.d[a] * sw;
    if constexpr (S)
      for (int i = 0; i < Jet<K, S>::kPairs; ++i) acc.dd[i] += x.dd[i] * sw;
    return;
  }
  for (int a = 0; a < x.n; ++a) acc.d[a] += x.d[a] * sw;
  for (int i = 0; i < Jet<K, S>::pairs(x.n); ++i) acc.dd[i] += x.dd[i] * sw;
}

// x = x * scale + offset
inline void affine(float& x, float scale, float offset) { x = x * scale + offset; }
template <int K, bool S>
inline void affine(Jet<K, S>& x, float scale, float offset) {
  x.v = x.v * scale + offset;
  for (int a = 0; a < x.n; ++a) x.d[a] *= scale;
  for (int i = 0; i < Jet<K, S>::pairs(x.n); ++i) x.dd[i] *= scale;
}

inline void apply(Activation act, float& x) { x = activate(act, x); }
template <int K, bool S>
inline void apply(Activation act, Jet<K, S>& x) {
  if (x.n == 0) {
    x.v = activate(act, x.v);
    return;
  }
  const ActValue f = activate_d2(act, x.v);
  x.v = f.f;
  if constexpr (S) {
    // chain rule: (f o x)_ab = f''(x) x_a x_b + f'(x) x_ab
    float* h = x.dd;
    for (int b = 0; b < x.n; ++b)
      for (int a = 0; a <= b; ++a, ++h) *h = f.d2f * x.d[a] * x.d[b] + f.df * *h;
  }
  for (int a = 0; a < x.n; ++a) x.d[a] *= f.df;
}

// out = x * y (element product of two variables, used by the GRU gates).
// Second derivatives first, then first, then the value: out may alias x or y.
inline void multiply(float& out, float x, float y) { out = x * y; }
template <int K, bool S>
inline void multiply(Jet<K, S>& out, const Jet<K, S>& x, const Jet<K, S>& y) {
  const uint8_t n = x.n > y.n ? x.n : y.n;
  auto d = [](const Jet<K, S>& j, int a) { return a < j.n ? j.d[a] : 0.0f; };
  const float xv = x.v, yv = y.v;
  if constexpr (S) {
    auto dd = [](const Jet<K, S>& j, int i, int b) { return b < j.n ? j.dd[i] : 0.0f; };
    for (int b = 0; b < n; ++b)
      for (int a = 0; a <= b; ++a) {
        const int i = Jet<K, S>::pair(a, b);
        out.dd[i] = dd(x, i, b) * yv + d(x, a) * d(y, b) + d(x, b) * d(y, a) + xv * dd(y, i, b);
      }
  }
  for (int a = 0; a < n; ++a) out.d[a] = d(x, a) * yv + xv * d(y, a);
  out.v = xv * yv;
  out.n = n;
}

}  // namespace nlsoft
