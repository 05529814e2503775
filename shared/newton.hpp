#pragma once
// Newton-Raphson on U (paper eq. NR): H (U+ - U) = -dJ/dU, H the full
// Hessian of eq. cost2, solved by LU with partial pivoting, iterated to a
// tolerance or a cap, each iterate clamped to the input limits.
//
// Safeguards, each reported in the result flags:
//   - if H with the second-order network term is singular or gives no descent
//     direction, the term is dropped (Gauss-Newton Hessian, positive
//     semi-definite by construction);
//   - if that is singular too (e.g. Lambda = 0 and a flat model), a scaled
//     gradient step is taken;
//   - a non-finite gradient leaves U unchanged.
// Whatever the parameters, U stays finite and inside [u_min, u_max].
#include <cmath>

#include "shared/cost.hpp"
#include "shared/derivatives.hpp"
#include "shared/lu.hpp"

namespace nlsoft {

enum StepFlag : uint8_t {
  kConverged = 1u << 0,         // max |dU| < nr_tol before the cap
  kCurvatureDropped = 1u << 1,  // fell back to the Gauss-Newton Hessian
  kGradientStep = 1u << 2,      // Hessian singular / non-finite: gradient step
  kNonFinite = 1u << 3,         // gradient not finite: U kept
  kClamped = 1u << 4,           // an input limit was active
  kBadSensor = 1u << 5,         // a sensor value was not finite (previous kept)
  kBadReference = 1u << 6,      // a reference value was not finite (held)
};

template <class Cap>
struct NewtonScratch {
  static constexpr int K = Derived<Cap>::K;
  HorizonDerivatives<Cap> D;
  CostTerms<Cap> C;
  float LU[K * K];
  int piv[K];
  float dU[K];
  ExactScratch<Cap> exact;
  FdScratch<Cap> fd;
};

struct NewtonResult {
  uint8_t iterations = 0;
  uint8_t flags = 0;
  float step = 0.0f;  // max |dU| of the last iteration
};

inline bool finite(float v) { return v - v == 0.0f; }

inline float clamp_to(float v, float lo, float hi) {
  if (!finite(v)) return 0.5f * (lo + hi);
  return v < lo ? lo : (v > hi ? hi : v);
}

namespace detail {

// Solves (H + diag(extra)) dU = -g into s.dU; false if singular / not descent.
template <class Cap>
bool newton_direction(NewtonScratch<Cap>& s, int k, const float* extra) {
  constexpr int K = Derived<Cap>::K;
  for (int a = 0; a < k; ++a)
    for (int b = 0; b < k; ++b) s.LU[a * K + b] = s.C.H[a * K + b] + (a == b && extra ? extra[a] : 0.0f);
  if (!lu_decompose(s.LU, k, K, s.piv)) return false;
  float descent = 0.0f;
  for (int a = 0; a < k; ++a) s.dU[a] = -s.C.g[a];
  lu_solve(s.LU, k, K, s.piv, s.dU);
  for (int a = 0; a < k; ++a) {
    if (!finite(s.dU[a])) return false;
    descent += s.C.g[a] * s.dU[a];
  }
  return descent <= 0.0f;
}

}  // namespace detail

// x0: input vector before the decision (see horizon.hpp); y_ref: N x n;
// U: Nc x m, the initial guess on entry and the solution on exit.
template <class Cap>
NewtonResult newton_solve(const Model<Cap>& M, const Params<Cap>& P, const float* x0, const float* y_ref,
                          float* U, NewtonScratch<Cap>& s) {
  const int m = M.m, k = P.Nc * m;
  const float* u_prev = x0;  // u(k-1) is the newest entry of the u-queue
  NewtonResult r;
  for (int a = 0; a < k; ++a) U[a] = clamp_to(U[a], P.u_min[a % m], P.u_max[a % m]);

  for (int it = 0; it < P.nr_max_iter; ++it) {
    if (P.mode == DerivMode::Fd)
      derivatives_fd(M, x0, U, P.N, P.Nc, P.eps, s.D, s.fd);
    else
      derivatives_exact(M, x0, U, P.N, P.Nc, s.D, s.exact);
    evaluate_cost(P, m, M.n, y_ref, U, u_prev, s.D, s.C);
    r.iterations = uint8_t(it + 1);

    bool grad_ok = true;
    for (int a = 0; a < k; ++a) grad_ok = grad_ok && finite(s.C.g[a]);
    if (!grad_ok) {
      r.flags |= kNonFinite;
      break;
    }
    if (!detail::newton_direction(s, k, s.C.curv)) {
      r.flags |= kCurvatureDropped;
      if (!detail::newton_direction(s, k, static_cast<const float*>(nullptr))) {
        // steepest descent scaled by the largest curvature we can trust
        float h = 0.0f;
        for (int a = 0; a < k; ++a) {
          const float d = std::fabs(s.C.H[a * Derived<Cap>::K + a]);
          if (finite(d) && d > h) h = d;
        }
        const float alpha = h > 0.0f ? 1.0f / h : 0.0f;
        for (int a = 0; a < k; ++a) s.dU[a] = -alpha * s.C.g[a];
        r.flags |= kGradientStep;
      }
    }
    float step = 0.0f;
    for (int a = 0; a < k; ++a) {
      const float lo = P.u_min[a % m], hi = P.u_max[a % m];
      const float want = U[a] + s.dU[a];
      const float next = clamp_to(want, lo, hi);
      if (next != want) r.flags |= kClamped;
      const float d = std::fabs(next - U[a]);
      if (d > step) step = d;
      U[a] = next;
    }
    r.step = step;
    if (step < P.nr_tol) {
      r.flags |= kConverged;
      break;
    }
  }
  return r;
}

}  // namespace nlsoft
