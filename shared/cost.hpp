#pragma once
// The cost J (the paper's eq. 2), its gradient dJ/dU (eq. 4) and its
// Hessian d2J/dU2 (eq. 5) in the Gauss-Newton form, a full
// (Nc m) x (Nc m) matrix:
//
//   J = sum_{j=N1..N} ||y_ref,j - y_hat,j||^2_Q            tracking
//     + sum_{j=0..Nc-1} ||du_j||^2_Lambda                  smoothness, du_0 = U_0 - u(k-1)
//     + sum_i sum_j [ s/(u + r/2 - b) + s/(r/2 + b - u) - 4s/r ]   barrier
//
//   g = -2 G' Q e + Lambda and barrier terms,   e = y_ref - y_hat, G = dY_hat/dU
//   H =  2 G' Q G + Lambda and barrier terms
//
// The Lambda term runs over time steps j (each du_j is an m-vector), and H
// couples every pair of unknowns; the published firmware collapsed both to a
// per-actuator scalar. H leaves out eq. 5's second-order network term
// -2 e' Q d2y/dU2: it costs more than the rest of the step to compute, makes
// H indefinite where the prediction misses the reference, and vanishes where
// it meets it; measured with it on the shipped models, tracking was the same
// (Swirl nRMSE 3.32 % with, 3.33 % without). Both derivative modes build this
// same system and differ only in how G is obtained.
#include "shared/hot_path.hpp"
#include "shared/capacity.hpp"
#include "shared/params.hpp"

// The control step's hot code is compiled for speed even in images built
// for size (-Os): measured on the Cortex-M4F, -Os here costs 2.3x the
// instructions per step (the accessors and the unrolled tangent loops are
// not inlined), while the rest of an image gains nothing from -O2.
NLSOFT_HOT_BEGIN

namespace nlsoft {

// The Newton system at one point U: J(U), g and H (symmetric: its lower
// triangle with the diagonal is written, the solver reads no more), and the
// predictions Y_hat(U) it was built from.
template <class Cap>
struct NewtonSystem {
  static constexpr int K = Dims<Cap>::K;
  float J = 0.0f;
  float g[K] = {};
  float H[K * K] = {};
  float Y[Cap::N * Cap::n] = {};
};

// The barrier walls sit at b - r/2 and b + r/2. Past a wall the terms would
// change sign; distances are floored so J, g and H stay finite and keep
// pushing back inside whatever u the clamp allowed. The constant -4s/r makes
// the term zero at the centre b.
struct Barrier {
  float s, b, r;
  float d1(float u) const { return floor_(u + 0.5f * r - b); }
  float d2(float u) const { return floor_(0.5f * r + b - u); }
  float floor_(float d) const {
    const float f = 1e-6f * r;
    return d > f ? d : f;
  }
  // value, gradient and curvature at u from the two reciprocals: s/a + s/c
  // - 4s/r, -s/a^2 + s/c^2, 2s/a^3 + 2s/c^3 with a = d1(u), c = d2(u)
  void eval(float u, float& value, float& grad, float& hess) const {
    const float ia = 1.0f / d1(u), ic = 1.0f / d2(u);
    const float sa = s * ia, sc = s * ic;
    value = sa + sc - 4.0f * s / r;
    grad = sc * ic - sa * ia;
    hess = 2.0f * (sa * ia * ia + sc * ic * ic);
  }
  float value(float u) const {
    float v, g, h;
    eval(u, v, g, h);
    return v;
  }
};

namespace detail {

// Small systems (the MCU capacities): J, g and H's lower triangle
// accumulate in locals over every row and unknown, K a compile-time
// count, and H's triangle is written once. All K rows: past k they are
// zero (G's columns there are), see newton.hpp. Inlined into
// build_system as the branch it was: the step's instructions are measured.
template <class Cap>
__attribute__((always_inline)) inline void build_small_system(const Params<Cap>& P, int m, int n, int k,
                                                              const Barrier& bar, const float* y_ref, const float* U,
                                                              const float* u_prev, const float* G,
                                                              NewtonSystem<Cap>& S) {
  constexpr int K = Dims<Cap>::K;
  constexpr int kT = K * (K + 1) / 2;
  float J = 0.0f, g[K], h[kT];
NLSOFT_UNROLL(8)
  for (int a = 0; a < K; ++a) g[a] = 0.0f;
NLSOFT_UNROLL(64)
  for (int i = 0; i < kT; ++i) h[i] = 0.0f;
  // tracking: J += e' Q e, g -= 2 G' Q e, H += 2 G' Q G
  for (int t = P.N1 - 1; t < P.N; ++t)
    for (int i = 0; i < n; ++i) {
      const int row = t * n + i;
      const float q = P.Q[i];
      const float e = y_ref[row] - S.Y[row];
      J += q * e * e;
      const float* __restrict Gr = G + row * K;
      int idx = 0;
NLSOFT_UNROLL(8)
      for (int a = 0; a < K; ++a) {
        const float qga = 2.0f * q * Gr[a];
        g[a] -= qga * e;
NLSOFT_UNROLL(8)
        for (int b = 0; b <= a; ++b) h[idx++] += qga * Gr[b];
      }
    }
  // smoothness (du_j = U_j - U_{j-1}) and the barrier, unknown by unknown;
  // unrolled, so h's diagonal is indexed by constants and h stays in registers
NLSOFT_UNROLL(8)
  for (int a = 0; a < K; ++a) {
    if (a >= k) break;
    const int i = Cap::Nc == 1 ? a : a % m, j = Cap::Nc == 1 ? 0 : a / m;
    const float L = P.Lambda[i];
    const float du = U[a] - (j == 0 ? u_prev[i] : U[a - m]);
    float bv, bg, bh;
    bar.eval(U[a], bv, bg, bh);
    J += L * du * du + bv;
    g[a] += 2.0f * L * du + bg;
    h[a * (a + 1) / 2 + a] += 2.0f * L + bh;
    if (Cap::Nc > 1 && j > 0) {  // dJ/dU_{j-1} of the same du_j
      const int b = a - m;
      g[b] -= 2.0f * L * du;
      h[b * (b + 1) / 2 + b] += 2.0f * L;
      h[a * (a + 1) / 2 + b] -= 2.0f * L;  // lower triangle: b < a
    }
  }
  S.J = J;
  int idx = 0;
NLSOFT_UNROLL(8)
  for (int a = 0; a < K; ++a) {
    S.g[a] = g[a];
NLSOFT_UNROLL(8)
    for (int b = 0; b <= a; ++b, ++idx) S.H[a * K + b] = h[idx];
  }
}

// Any K: J, g and H's lower triangle accumulated in place.
template <class Cap>
__attribute__((always_inline)) inline void build_any_system(const Params<Cap>& P, int m, int n, int k,
                                                            const Barrier& bar, const float* y_ref, const float* U,
                                                            const float* u_prev, const float* G,
                                                            NewtonSystem<Cap>& S) {
  constexpr int K = Dims<Cap>::K;
  S.J = 0.0f;
  for (int a = 0; a < K; ++a) {
    S.g[a] = 0.0f;
    for (int b = 0; b <= a; ++b) S.H[a * K + b] = 0.0f;
  }
  // tracking: J += e' Q e, g -= 2 G' Q e, H += 2 G' Q G
  for (int t = P.N1 - 1; t < P.N; ++t)
    for (int i = 0; i < n; ++i) {
      const int row = t * n + i;
      const float q = P.Q[i];
      const float e = y_ref[row] - S.Y[row];
      S.J += q * e * e;
      const float* __restrict Gr = G + row * K;
      for (int a = 0; a < k; ++a) {
        const float qga = 2.0f * q * Gr[a];
        S.g[a] -= qga * e;
        float* __restrict Ha = S.H + a * K;
        for (int b = 0; b <= a; ++b) Ha[b] += qga * Gr[b];
      }
    }

  // smoothness: du_j = U_j - U_{j-1}; dJ/dU_j = 2 Lambda (du_j - du_{j+1})
  for (int j = 0; j < P.Nc; ++j) {
    for (int i = 0; i < m; ++i) {
      const float L = P.Lambda[i];
      const float prev = j == 0 ? u_prev[i] : U[(j - 1) * m + i];
      const float du = U[j * m + i] - prev;
      S.J += L * du * du;
      const int a = j * m + i;
      S.g[a] += 2.0f * L * du;
      S.H[a * K + a] += 2.0f * L;
      if (j > 0) {
        const int b = (j - 1) * m + i;
        S.g[b] -= 2.0f * L * du;
        S.H[b * K + b] += 2.0f * L;
        S.H[a * K + b] -= 2.0f * L;  // lower triangle: b < a
      }
    }
  }

  // barrier (Soloway): separable, diagonal
  for (int a = 0; a < k; ++a) {
    float bv, bg, bh;
    bar.eval(U[a], bv, bg, bh);
    S.J += bv;
    S.g[a] += bg;
    S.H[a * K + a] += bh;
  }
}

}  // namespace detail

// y_ref: N x n rows for y(k+1) ... y(k+N); U: Nc x m; u_prev: u(k-1);
// S.Y: the predictions at U; G: their Jacobian, N n rows of K.
template <class Cap>
void build_system(const Params<Cap>& P, int m, int n, const float* y_ref, const float* U, const float* u_prev,
                  const float* G, NewtonSystem<Cap>& S) {
  const int k = Dims<Cap>::unknowns(P.Nc, m);
  const Barrier bar{P.s, P.b, P.r};
  if constexpr (Dims<Cap>::K <= 8)
    detail::build_small_system(P, m, n, k, bar, y_ref, U, u_prev, G, S);
  else
    detail::build_any_system(P, m, n, k, bar, y_ref, U, u_prev, G, S);
}

// J alone, from predictions Y (no derivatives).
template <class Cap>
float cost_value(const Params<Cap>& P, int m, int n, const float* y_ref, const float* U,
                 const float* u_prev, const float* Y) {
  float J = 0.0f;
  for (int t = P.N1 - 1; t < P.N; ++t)
    for (int i = 0; i < n; ++i) {
      const float e = y_ref[t * n + i] - Y[t * n + i];
      J += P.Q[i] * e * e;
    }
  const Barrier bar{P.s, P.b, P.r};
  for (int j = 0; j < P.Nc; ++j)
    for (int i = 0; i < m; ++i) {
      const float u = U[j * m + i];
      const float du = u - (j == 0 ? u_prev[i] : U[(j - 1) * m + i]);
      J += P.Lambda[i] * du * du + bar.value(u);
    }
  return J;
}

}  // namespace nlsoft

NLSOFT_HOT_END
