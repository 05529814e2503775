#pragma once
// The cost J (paper eq. "cost"), its gradient dJ/dU (eq. cost1) and its
// Hessian d2J/dU2 (eq. cost2) as a full (Nc m) x (Nc m) matrix.
//
//   J = sum_{j=N1..N} ||y_ref,j - y_hat,j||^2_Q            tracking
//     + sum_{j=0..Nc-1} ||du_j||^2_Lambda                  smoothness, du_0 = U_0 - u(k-1)
//     + sum_i sum_j [ s/(u + r/2 - b) + s/(r/2 + b - u) - 4/r ]   barrier
//
// The Lambda term runs over time steps j (each du_j is an m-vector), and the
// Hessian couples every pair of unknowns; the published firmware collapsed
// both to a per-actuator scalar. The second-order network term is the full
// curvature in exact mode and its diagonal in fd mode (the paper's stencil).
#include <cmath>

#include "shared/derivatives.hpp"
#include "shared/params.hpp"

namespace nlsoft {

template <class Cap>
struct CostTerms {
  static constexpr int K = Derived<Cap>::K;
  float J = 0.0f;
  float g[K] = {};
  float H[K * K] = {};     // Gauss-Newton part + Lambda + barrier: positive semi-definite
  float curv[K * K] = {};  // second-order network term -2 sum e'Q d2y/dU2 (added by the solver):
                           // full in exact mode, diagonal in fd mode
};

// The barrier walls sit at b - r/2 and b + r/2. Past a wall the terms would
// change sign; distances are floored so J, g and H stay finite and keep
// pushing back inside whatever u the clamp allowed.
struct Barrier {
  float s, b, r;
  float d1(float u) const { return floor_(u + 0.5f * r - b); }
  float d2(float u) const { return floor_(0.5f * r + b - u); }
  float floor_(float d) const {
    const float f = 1e-6f * r;
    return d > f ? d : f;
  }
  float value(float u) const { return s / d1(u) + s / d2(u) - 4.0f / r; }
  float grad(float u) const {
    const float a = d1(u), c = d2(u);
    return -s / (a * a) + s / (c * c);
  }
  float hess(float u) const {
    const float a = d1(u), c = d2(u);
    return 2.0f * s / (a * a * a) + 2.0f * s / (c * c * c);
  }
};

// y_ref: N x n rows for y(k+1) ... y(k+N); U: Nc x m; u_prev: u(k-1).
template <class Cap>
void evaluate_cost(const Params<Cap>& P, int m, int n, const float* y_ref, const float* U,
                   const float* u_prev, const HorizonDerivatives<Cap>& D, CostTerms<Cap>& C) {
  constexpr int K = Derived<Cap>::K;
  const int k = P.Nc * m;
  C.J = 0.0f;
  for (int a = 0; a < k; ++a) {
    C.g[a] = 0.0f;
    for (int b = 0; b < k; ++b) C.H[a * K + b] = C.curv[a * K + b] = 0.0f;
  }

  // tracking: J += e' Q e, g -= 2 G' Q e, H += 2 G' Q G, curv -= 2 e' Q D2
  for (int t = P.N1 - 1; t < P.N; ++t) {
    for (int i = 0; i < n; ++i) {
      const int row = t * n + i;
      const float q = P.Q[i];
      const float e = y_ref[row] - D.Y[row];
      C.J += q * e * e;
      const float* G = D.G + row * K;
      const float* D2 = D.D2 + row * K;
      for (int a = 0; a < k; ++a) {
        C.g[a] -= 2.0f * q * e * G[a];
        const float qga = 2.0f * q * G[a];
        for (int b = a; b < k; ++b) C.H[a * K + b] += qga * G[b];
      }
      const float w = -2.0f * q * e;
      if (D.jets) {
        if constexpr (Cap::second_order) {
          const JetOf<Cap>& y = D.jets[row];
          for (int b = 0; b < k && b < y.n; ++b)
            for (int a = 0; a <= b; ++a) C.curv[a * K + b] += w * y.dd[JetOf<Cap>::pair(a, b)];
        }
      } else {
        for (int a = 0; a < k; ++a) C.curv[a * K + a] += w * D2[a];
      }
    }
  }

  // smoothness: du_j = U_j - U_{j-1}; dJ/dU_j = 2 Lambda (du_j - du_{j+1})
  for (int j = 0; j < P.Nc; ++j) {
    for (int i = 0; i < m; ++i) {
      const float L = P.Lambda[i];
      const float prev = j == 0 ? u_prev[i] : U[(j - 1) * m + i];
      const float du = U[j * m + i] - prev;
      C.J += L * du * du;
      const int a = j * m + i;
      C.g[a] += 2.0f * L * du;
      C.H[a * K + a] += 2.0f * L;
      if (j > 0) {
        const int b = (j - 1) * m + i;
        C.g[b] -= 2.0f * L * du;
        C.H[b * K + b] += 2.0f * L;
        C.H[b * K + a] -= 2.0f * L;  // upper triangle: b < a
      }
    }
  }

  // barrier (Soloway): separable, diagonal
  const Barrier bar{P.s, P.b, P.r};
  for (int a = 0; a < k; ++a) {
    C.J += bar.value(U[a]);
    C.g[a] += bar.grad(U[a]);
    C.H[a * K + a] += bar.hess(U[a]);
  }

  // mirror the upper triangles
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b) {
      C.H[b * K + a] = C.H[a * K + b];
      C.curv[b * K + a] = C.curv[a * K + b];
    }
}

}  // namespace nlsoft

namespace nlsoft {

// J alone, from a plain rollout Y (no derivatives): for reporting.
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
