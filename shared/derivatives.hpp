#pragma once
// dY_hat/dU and the curvature d2Y_hat/dU2 over the whole horizon, in the two
// modes of the product:
//   fd     the paper's central stencil (eqs. first_derivative1 and
//          second_derivative1), applied to U directly: 2K+1 horizon rollouts,
//          second derivatives along each direction only (the diagonal).
//   exact  forward-mode chain rule through the layers (jet.hpp): one rollout,
//          every second derivative (the full curvature, so Newton converges
//          quadratically even where the prediction cannot meet the reference).
// Both differentiate the recursion itself; the paper's X_j = X shortcut is not
// taken, so both modes see the same function and tests hold one to the other.
#include "shared/horizon.hpp"
#include "shared/jet.hpp"

namespace nlsoft {

// The jet type of a capacity: K directions, second derivatives if it asks.
template <class Cap>
using JetOf = Jet<Derived<Cap>::K, Cap::second_order>;

template <class Cap>
struct HorizonDerivatives {
  static constexpr int K = Derived<Cap>::K;
  float Y[Cap::N * Cap::n];        // Y[j*n + i] = y_hat_i(k+1+j)
  float G[Cap::N * Cap::n * K];    // G[(j*n + i)*K + a] = dY[j][i] / dU_a
  float D2[Cap::N * Cap::n * K];   // fd: D2[(j*n + i)*K + a] = d2Y[j][i] / dU_a^2
  // exact: the predictions as jets, with every second derivative
  // (Jet::dd); null in fd mode.
  const JetOf<Cap>* jets = nullptr;
};

template <class Cap>
struct ExactScratch {
  static constexpr int K = Derived<Cap>::K;
  JetOf<Cap> U[K];
  JetOf<Cap> Y[Cap::N * Cap::n];
  HorizonScratch<Cap, JetOf<Cap>> h;
};

template <class Cap>
struct FdScratch {
  float U[Derived<Cap>::K];
  float Yp[Cap::N * Cap::n];
  float Ym[Cap::N * Cap::n];
  HorizonScratch<Cap, float> h;
};

template <class Cap>
void derivatives_exact(const Model<Cap>& M, const float* x0, const float* U, int N, int Nc,
                       HorizonDerivatives<Cap>& D, ExactScratch<Cap>& s, const ConstantInputs& c = {}) {
  constexpr int K = Derived<Cap>::K;
  const int k = Nc * M.m;
  for (int a = 0; a < k; ++a) {
    JetOf<Cap>& u = s.U[a];
    u.v = U[a];
    u.n = uint8_t(k);
    for (int b = 0; b < k; ++b) u.d[b] = u.dd[b] = 0.0f;
    u.d[a] = 1.0f;
  }
  predict_horizon(M, x0, s.U, N, Nc, s.Y, s.h, c);
  for (int r = 0; r < N * M.n; ++r) {
    const JetOf<Cap>& y = s.Y[r];
    D.Y[r] = y.v;
    for (int a = 0; a < k; ++a) {
      D.G[r * K + a] = a < y.n ? y.d[a] : 0.0f;
      D.D2[r * K + a] = Cap::second_order && a < y.n ? y.dd[JetOf<Cap>::pair(a, a)] : 0.0f;
    }
  }
  D.jets = s.Y;
}

template <class Cap>
void derivatives_fd(const Model<Cap>& M, const float* x0, const float* U, int N, int Nc, float eps,
                    HorizonDerivatives<Cap>& D, FdScratch<Cap>& s, const ConstantInputs& c = {}) {
  constexpr int K = Derived<Cap>::K;
  const int k = Nc * M.m;
  const int rows = N * M.n;
  D.jets = nullptr;
  predict_horizon(M, x0, U, N, Nc, D.Y, s.h, c);
  for (int a = 0; a < k; ++a) s.U[a] = U[a];
  const float inv2e = 0.5f / eps, inve2 = 1.0f / (eps * eps);
  for (int a = 0; a < k; ++a) {
    s.U[a] = U[a] + eps;
    predict_horizon(M, x0, s.U, N, Nc, s.Yp, s.h, c);
    s.U[a] = U[a] - eps;
    predict_horizon(M, x0, s.U, N, Nc, s.Ym, s.h, c);
    s.U[a] = U[a];
    for (int r = 0; r < rows; ++r) {
      D.G[r * K + a] = (s.Yp[r] - s.Ym[r]) * inv2e;
      D.D2[r * K + a] = (s.Yp[r] - 2.0f * D.Y[r] + s.Ym[r]) * inve2;
    }
  }
}

}  // namespace nlsoft
