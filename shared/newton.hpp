#pragma once
// Newton-Raphson on U (paper eq. NR): H (U+ - U) = -dJ/dU, H the full
// Hessian of eq. cost2, solved by LU with partial pivoting, iterated to a
// tolerance or a cap, each iterate kept inside the input limits.
//
// Globalisation, because the plain Newton step is only as good as the local
// quadratic model: the learned model is piecewise linear (ReLU) and, with
// redundant actuators and Q >> Lambda (the paper's tunings), H is
// conditioned 1e8, so an undamped step can be hundreds of times the input
// range. Each iteration therefore tries the undamped step first and accepts
// it only if it lowers J (Armijo); otherwise it damps, H + mu I with mu
// growing tenfold (Levenberg-Marquardt), which bends the step towards the
// gradient and shortens it. The damping that worked is remembered and eased
// tenfold after each success, so near the optimum the undamped step returns
// and convergence stays quadratic. Inputs held at a limit by the gradient drop out
// of the system (projected Newton).
//
// Whatever the parameters, U stays finite and inside [u_min, u_max]; what
// happened is reported in the result flags.
#include <cmath>

#include "shared/cost.hpp"
#include "shared/derivatives.hpp"
#include "shared/lu.hpp"

namespace nlsoft {

enum StepFlag : uint8_t {
  kConverged = 1u << 0,         // max |dU| < nr_tol before the cap
  kDamped = 1u << 1,            // the undamped Newton step did not lower J: damped
  kSingular = 1u << 2,          // the Hessian was singular or not finite at least once
  kNonFinite = 1u << 3,         // gradient not finite: U kept
  kClamped = 1u << 4,           // an input limit was active
  kBadSensor = 1u << 5,         // a sensor value was not finite (previous kept)
  kBadReference = 1u << 6,      // a reference value was not finite (held)
  kNoDescent = 1u << 7,         // no step along the Newton direction lowered J: U kept
};

template <class Cap>
struct NewtonScratch {
  static constexpr int K = Derived<Cap>::K;
  HorizonDerivatives<Cap> D;
  CostTerms<Cap> C;
  float LU[K * K];
  int piv[K];
  float dU[K];
  // Levenberg-Marquardt damping carried from one iteration (and one control
  // step) to the next, as a fraction of the Hessian's largest diagonal
  // entry: consecutive problems are alike, so most iterations need one try.
  float mu_rel = 0.0f;
  float pre[Cap::width];  // the first layer's constant part for this step's x0
  ConstantInputs constant;
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

// Solves (H + curv + mu I) dU = -g into s.dU over the free unknowns; those
// held at a limit (active[a]) get dU = 0 and drop out of the system. False
// if singular, not finite, or not a descent direction.
template <class Cap>
bool newton_direction(NewtonScratch<Cap>& s, int k, float mu, const bool* active) {
  constexpr int K = Derived<Cap>::K;
  for (int a = 0; a < k; ++a)
    for (int b = 0; b < k; ++b) {
      float h = s.C.H[a * K + b] + s.C.curv[a * K + b] + (a == b ? mu : 0.0f);
      if (active[a] || active[b]) h = a == b ? 1.0f : 0.0f;
      s.LU[a * K + b] = h;
    }
  if (!lu_decompose(s.LU, k, K, s.piv)) return false;
  float descent = 0.0f;
  for (int a = 0; a < k; ++a) s.dU[a] = active[a] ? 0.0f : -s.C.g[a];
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
  s.constant = constant_inputs(M, x0, s.pre);

  for (int it = 0; it < P.nr_max_iter; ++it) {
    if (P.mode == DerivMode::Fd)
      derivatives_fd(M, x0, U, P.N, P.Nc, P.eps, s.D, s.fd, s.constant);
    else
      derivatives_exact(M, x0, U, P.N, P.Nc, s.D, s.exact, s.constant);
    evaluate_cost(P, m, M.n, y_ref, U, u_prev, s.D, s.C);
    r.iterations = uint8_t(it + 1);

    bool grad_ok = true;
    for (int a = 0; a < k; ++a) grad_ok = grad_ok && finite(s.C.g[a]);
    if (!grad_ok) {
      r.flags |= kNonFinite;
      break;
    }
    bool active[Derived<Cap>::K];
    bool any_free = false;
    float hmax = 0.0f;
    for (int a = 0; a < k; ++a) {
      const float lo = P.u_min[a % m], hi = P.u_max[a % m];
      active[a] = (U[a] <= lo && s.C.g[a] > 0.0f) || (U[a] >= hi && s.C.g[a] < 0.0f);
      any_free = any_free || !active[a];
      const float d = std::fabs(s.C.H[a * Derived<Cap>::K + a]);
      if (finite(d) && d > hmax) hmax = d;
    }
    if (!any_free) {  // every input pinned at a limit by the gradient: optimal as it is
      r.flags |= kConverged | kClamped;
      r.step = 0.0f;
      break;
    }

    // Damping from the last success, raised tenfold until J decreases.
    const float hscale = hmax > 0.0f ? hmax : 1.0f;
    float mu = s.mu_rel * hscale, step = 0.0f;
    bool accepted = false, clamped = false;
    for (int tries = 0; tries < 8; ++tries) {
      if (tries > 0) mu = mu == 0.0f ? 1e-4f * hscale : 10.0f * mu;
      if (mu > 0.0f) r.flags |= kDamped;
      if (!detail::newton_direction(s, k, mu, active)) {
        r.flags |= kSingular;
        continue;
      }
      float slope = 0.0f;
      step = 0.0f;
      clamped = false;
      for (int a = 0; a < k; ++a) {
        const float want = U[a] + s.dU[a];
        s.fd.U[a] = clamp_to(want, P.u_min[a % m], P.u_max[a % m]);
        clamped = clamped || s.fd.U[a] != want;
        slope += s.C.g[a] * (s.fd.U[a] - U[a]);
        const float d = std::fabs(s.fd.U[a] - U[a]);
        if (d > step) step = d;
      }
      // Small steps are taken on the quadratic model's word: within 2 % of
      // the input range it is trustworthy, and a float rollout could not
      // confirm them anyway (at 1 kHz a 0.01 N/kg change moves y by 5e-9 m
      // per step, below float resolution at 1 m). The rollout guards the big
      // steps, which are the ones that go wrong.
      bool small = true;
      for (int a = 0; a < k && small; ++a)
        small = std::fabs(s.fd.U[a] - U[a]) <= 0.02f * (P.u_max[a % m] - P.u_min[a % m]);
      if (small || step < P.nr_tol) {
        accepted = true;
        break;
      }
      predict_horizon(M, x0, s.fd.U, P.N, P.Nc, s.fd.Yp, s.fd.h, s.constant);
      const float J = cost_value(P, m, M.n, y_ref, s.fd.U, u_prev, s.fd.Yp);
      if (J <= s.C.J + 1e-4f * slope) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      r.flags |= kNoDescent;
      r.step = 0.0f;
      s.mu_rel = 0.0f;
      break;
    }
    s.mu_rel = mu / hscale < 1e-6f ? 0.0f : 0.1f * mu / hscale;
    if (clamped) r.flags |= kClamped;
    for (int a = 0; a < k; ++a) U[a] = s.fd.U[a];
    r.step = step;
    if (step < P.nr_tol) {
      r.flags |= kConverged;
      break;
    }
  }
  return r;
}

}  // namespace nlsoft
