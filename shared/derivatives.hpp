#pragma once
// Reference derivatives dY_hat/dU over the whole horizon, written for
// clarity on the generic network code (forward.hpp, horizon.hpp); tests hold
// the controller's fast rollout (rollout.hpp) to them:
//   jets     forward-mode chain rule through the layers (jet.hpp): one
//            rollout with K directions per value, std::tanh / std::exp;
//   stencil  the paper's central difference (eq. 7)
//            applied to U directly: 2K + 1 horizon rollouts.
// Both differentiate the recursion itself; the paper's X_j = X shortcut is
// not taken, so both see the same function.
#include "shared/horizon.hpp"
#include "shared/jet.hpp"

namespace nlsoft {

template <class Cap>
using JetOf = Jet<Dims<Cap>::K>;

template <class Cap>
struct HorizonDerivatives {
  static constexpr int K = Dims<Cap>::K;
  float Y[Cap::N * Cap::n];      // Y[j*n + i] = y_hat_i(k+1+j)
  float G[Cap::N * Cap::n * K];  // G[(j*n + i)*K + a] = dY[j][i] / dU_a
};

template <class Cap>
struct JetScratch {
  static constexpr int K = Dims<Cap>::K;
  JetOf<Cap> U[K];
  JetOf<Cap> Y[Cap::N * Cap::n];
  HorizonScratch<Cap, JetOf<Cap>> h;
};

template <class Cap>
struct StencilScratch {
  float U[Dims<Cap>::K];
  float Yp[Cap::N * Cap::n];
  float Ym[Cap::N * Cap::n];
  HorizonScratch<Cap, float> h;
};

template <class Cap>
void derivatives_jets(const Model<Cap>& M, const float* x0, const float* U, int N, int Nc,
                      HorizonDerivatives<Cap>& D, JetScratch<Cap>& s) {
  constexpr int K = Dims<Cap>::K;
  const int k = Nc * M.m;
  for (int a = 0; a < k; ++a) {
    JetOf<Cap>& u = s.U[a];
    u.v = U[a];
    u.n = uint8_t(k);
    for (int b = 0; b < k; ++b) u.d[b] = 0.0f;
    u.d[a] = 1.0f;
  }
  predict_horizon(M, x0, s.U, N, Nc, s.Y, s.h);
  for (int r = 0; r < N * M.n; ++r) {
    const JetOf<Cap>& y = s.Y[r];
    D.Y[r] = y.v;
    for (int a = 0; a < K; ++a) D.G[r * K + a] = a < k && a < y.n ? y.d[a] : 0.0f;
  }
}

template <class Cap>
void derivatives_stencil(const Model<Cap>& M, const float* x0, const float* U, int N, int Nc, float eps,
                         HorizonDerivatives<Cap>& D, StencilScratch<Cap>& s) {
  constexpr int K = Dims<Cap>::K;
  const int k = Nc * M.m;
  const int rows = N * M.n;
  predict_horizon(M, x0, U, N, Nc, D.Y, s.h);
  for (int a = 0; a < k; ++a) s.U[a] = U[a];
  const float inv2e = 0.5f / eps;
  for (int a = 0; a < K; ++a) {
    if (a >= k) {
      for (int r = 0; r < rows; ++r) D.G[r * K + a] = 0.0f;
      continue;
    }
    s.U[a] = U[a] + eps;
    predict_horizon(M, x0, s.U, N, Nc, s.Yp, s.h);
    s.U[a] = U[a] - eps;
    predict_horizon(M, x0, s.U, N, Nc, s.Ym, s.h);
    s.U[a] = U[a];
    for (int r = 0; r < rows; ++r) D.G[r * K + a] = (s.Yp[r] - s.Ym[r]) * inv2e;
  }
}

}  // namespace nlsoft
