#pragma once
// Newton-Raphson on U (the paper's eq. 3): H (U+ - U) = -dJ/dU with H the full
// Gauss-Newton Hessian of eq. 5 (cost.hpp), solved by LDL^T, iterated to
// a tolerance or a cap, each iterate kept inside the input limits.
//
// Globalisation, because the plain Newton step is only as good as the local
// quadratic model: with redundant actuators and Q >> Lambda (the paper's
// tunings) H is conditioned ~1e8, and the undamped step can be many times the
// input range. Every step is therefore damped, (H + mu h I) dU = -g with h
// H's largest diagonal entry (Levenberg-Marquardt), and mu is a trust
// decision made once per iteration, not by retries: the next iteration's
// linearisation measures J at the point the step reached anyway, so its actual
// reduction is compared with the quadratic model's prediction there;
// mu shrinks after a good step and grows after a poor one, and a step that
// raised J is undone and solved again from the kept system with more
// damping, no extra rollout. mu persists from one control step to the next
// (SolverState): consecutive problems are alike. The last step of a solve is
// checked by one plain rollout, which also gives the predicted path at the U
// applied. Inputs held at a limit by the gradient drop out of the system
// (projected Newton).
//
// Both derivative modes solve this same system; they differ only in how the
// Jacobian G = dY_hat/dU is obtained (linearise()).
//
// Whatever the parameters, U stays finite and inside [u_min, u_max]; what
// happened is reported in the result flags.
#include <cmath>

#include "shared/hot_path.hpp"
#include "shared/cost.hpp"
#include "shared/ldlt.hpp"
#include "shared/kernels.hpp"

// The control step's hot code is compiled for speed even in images built
// for size (-Os): measured on the Cortex-M4F, -Os here costs 2.3x the
// instructions per step (the accessors and the unrolled tangent loops are
// not inlined), while the rest of an image gains nothing from -O2.
NLSOFT_HOT_BEGIN

namespace nlsoft {

enum StepFlag : uint8_t {
  kConverged = 1u << 0,         // max |dU| < nr_tol before the cap
  kDamped = 1u << 1,            // a step raised J and was solved again with more damping
  kSingular = 1u << 2,          // the damped system was not positive definite at least once
  kNonFinite = 1u << 3,         // J or its gradient not finite: U kept
  kClamped = 1u << 4,           // an input limit was active
  kBadSensor = 1u << 5,         // a sensor value was not finite (previous kept)
  kBadReference = 1u << 6,      // a reference value was not finite (held)
  kNoDescent = 1u << 7,         // the last step raised J: U kept at the point before it
};

// What the solver carries from one control step to the next.
struct SolverState {
  static constexpr float kMuStart = 1e-4f, kMuMin = 1e-6f, kMuMax = 1e3f;
  float mu = kMuStart;  // Levenberg damping, relative to H's largest diagonal entry
};

// Caller-owned working memory of one solve; nothing in it outlives the call
// but the predicted path the result points to.
template <class Cap>
struct SolverScratch {
  static constexpr int K = Dims<Cap>::K;
  float pre[(Cap::nd + 1) * Cap::width];  // the first layer's constant part for this step's x0 (kernels.hpp)
  ConstantInputs constant;
  float G[Cap::N * Cap::n * K];     // dY_hat/dU at the point being linearised
  NewtonSystem<Cap> sys[2];         // at U, and at the point the last step left
  float U_base[K];                  // that point
  float A[K * K];                   // the damped system, factored
  float dU[K];
  float U_fd[K];                    // fd: U with one input moved by +-eps
  float U_pad[K];                   // a padded system's unknowns (the caller's U holds only Nc·m)
  float Y_plus[Cap::N * Cap::n];    // fd: the predictions there
  float Y_minus[Cap::N * Cap::n];
  RolloutScratch<Cap> roll;
};

struct NewtonResult {
  uint8_t iterations = 0;        // linearisations (rollouts with derivatives)
  uint8_t flags = 0;
  float step = 0.0f;             // max |dU| of the last step taken
  float cost = 0.0f;             // J at the U returned
  const float* y_hat = nullptr;  // Y_hat at the U returned, N x n, in the scratch
};

inline bool finite(float v) { return v - v == 0.0f; }

inline float clamp_to(float v, float lo, float hi) {
  if (!finite(v)) return 0.5f * (lo + hi);
  return v < lo ? lo : (v > hi ? hi : v);
}

namespace detail {

// Y_hat(U) and G = dY_hat/dU: in `exact` mode by the chain rule in the same
// rollout; in `fd` mode by the paper's central stencil, 2 Nc m more rollouts.
template <class Cap>
void linearise(const Model<Cap>& M, const RolloutKernels<Cap>& kern, const Params<Cap>& P, const float* x0,
               const float* U, float* Y, SolverScratch<Cap>& s) {
  constexpr int K = Dims<Cap>::K;
  if (P.mode != DerivMode::Fd) {
    kern.jacobian(M, x0, U, P.N, P.Nc, s.constant, Y, s.G, s.roll);
    return;
  }
  const int k = Dims<Cap>::unknowns(P.Nc, M.m), rows = P.N * M.n;
  kern.values(M, x0, U, P.N, P.Nc, s.constant, Y, nullptr, s.roll);
  for (int a = 0; a < k; ++a) s.U_fd[a] = U[a];
  const float inv2e = 0.5f / P.eps;
  if (kern.stencil) {  // from the rollout at U just run
    for (int a = 0; a < k; ++a) {
      kern.stencil(M, x0, P.N, s.constant, a, P.eps, s.Y_plus, s.roll);
      kern.stencil(M, x0, P.N, s.constant, a, -P.eps, s.Y_minus, s.roll);
      for (int r = 0; r < rows; ++r) s.G[r * K + a] = (s.Y_plus[r] - s.Y_minus[r]) * inv2e;
    }
    for (int a = k; a < K; ++a)
      for (int r = 0; r < rows; ++r) s.G[r * K + a] = 0.0f;
    return;
  }
  for (int a = 0; a < k; ++a) {
    s.U_fd[a] = U[a] + P.eps;
    kern.values(M, x0, s.U_fd, P.N, P.Nc, s.constant, s.Y_plus, nullptr, s.roll);
    s.U_fd[a] = U[a] - P.eps;
    kern.values(M, x0, s.U_fd, P.N, P.Nc, s.constant, s.Y_minus, nullptr, s.roll);
    s.U_fd[a] = U[a];
    for (int r = 0; r < rows; ++r) s.G[r * K + a] = (s.Y_plus[r] - s.Y_minus[r]) * inv2e;
  }
  for (int a = k; a < K; ++a)  // no unknown there: as the exact kernels leave it
    for (int r = 0; r < rows; ++r) s.G[r * K + a] = 0.0f;
}

// Solves (H + mu h I) dU = -g over the free unknowns; those held at a limit
// (active[a]) get dU = 0 and drop out. False if not positive definite.
template <class Cap>
bool damped_direction(const NewtonSystem<Cap>& S, int k, float damping, const bool* active, bool any_active,
                      SolverScratch<Cap>& s) {
  constexpr int K = Dims<Cap>::K;
  if constexpr (K <= 8) k = K;  // newton_solve pads small systems: constant trip counts
NLSOFT_UNROLL(8)
  for (int a = 0; a < k; ++a)
NLSOFT_UNROLL(8)
    for (int b = 0; b <= a; ++b) s.A[a * K + b] = S.H[a * K + b] + (a == b ? damping : 0.0f);
  if (any_active)  // rows and columns of the held unknowns become the identity's
    for (int a = 0; a < k; ++a)
      for (int b = 0; b <= a; ++b)
        if (active[a] || active[b]) s.A[a * K + b] = a == b ? 1.0f : 0.0f;
  if constexpr (K <= 8) {  // k == K here (newton_solve pads small systems)
    if (!ldlt_decompose_fixed<K>(s.A)) return false;
  } else {
    if (!ldlt_decompose(s.A, k, K)) return false;
  }
NLSOFT_UNROLL(8)
  for (int a = 0; a < k; ++a) s.dU[a] = active[a] ? 0.0f : -S.g[a];
  if constexpr (K <= 8)
    ldlt_solve_fixed<K>(s.A, s.dU);
  else
    ldlt_solve(s.A, k, K, s.dU);
  float probe = 0.0f;  // x * 0 is 0 for finite x, NaN otherwise
NLSOFT_UNROLL(8)
  for (int a = 0; a < k; ++a) probe += s.dU[a] * 0.0f;
  return probe == 0.0f;
}

inline float clamp_mu(float mu) {
  return mu < SolverState::kMuMin ? SolverState::kMuMin : (mu > SolverState::kMuMax ? SolverState::kMuMax : mu);
}

}  // namespace detail

// kern: select_kernels() of M; x0: input vector before the decision (see
// horizon.hpp); y_ref: N x n; U: Nc x m, the initial guess on entry and the
// solution on exit.
template <class Cap>
NewtonResult newton_solve(const Model<Cap>& M, const RolloutKernels<Cap>& kern, const Params<Cap>& P,
                          const float* x0, const float* y_ref, float* U, SolverState& st, SolverScratch<Cap>& s) {
  constexpr int K = Dims<Cap>::K;
  const int m = Dims<Cap>::full_k ? Cap::m : M.m, n = M.n, k = Dims<Cap>::unknowns(P.Nc, m);
  const float* u_prev = x0;  // u(k-1) is the newest entry of the u-queue
  NewtonResult r;
  // Small systems (the MCU capacities) run over the capacity's K, so every
  // loop below has a constant trip count; unknowns past k are held at their
  // value like inputs at a limit, and their gradient and Hessian are zero.
  constexpr bool kPadded = K <= 8;
  const int kk = kPadded ? K : k;
  // The caller's U holds k = Nc·m values: a padded system works on a copy
  // of K, and only the first k go back.
  float* const U_out = U;
  if (kPadded) {
NLSOFT_UNROLL(8)
    for (int a = 0; a < K; ++a) s.U_pad[a] = a < k ? U[a] : 0.0f;
    U = s.U_pad;
  }
  float lo[K], hi[K];
NLSOFT_UNROLL(8)
  for (int a = 0, i = 0; a < kk; ++a, i = i + 1 == m ? 0 : i + 1) {  // i = a % m
    lo[a] = a < k ? P.u_min[i] : -3.0e38f;
    hi[a] = a < k ? P.u_max[i] : 3.0e38f;
    U[a] = clamp_to(U[a], lo[a], hi[a]);
  }
  s.constant = kern.constant(M, x0, s.pre);
  if (!finite(st.mu)) st.mu = SolverState::kMuStart;
  st.mu = detail::clamp_mu(st.mu);

  NewtonSystem<Cap>* cur = &s.sys[0];   // the system at U
  NewtonSystem<Cap>* base = &s.sys[1];  // the system at s.U_base
  auto swap_systems = [&] {
    NewtonSystem<Cap>* t = cur;
    cur = base;
    base = t;
  };
  bool pending = false;  // U is a step from U_base whose J is not known yet
  float predicted = 0.0f;
  // The trust decision on a step from `base`: actual against predicted
  // reduction. A reduction below J's float rounding (1e-4 J) cannot be
  // measured by a rollout (msd at 1 kHz: 0.01 N/kg moves y by 5e-9 m per
  // step, below float resolution at 1 m), so there the quadratic model is
  // taken at its word. False: the step raised J; undo it.
  auto judge = [&](float J_new) {
    const float actual = base->J - J_new, noise = 1e-4f * base->J;
    if (!(actual >= -noise)) return false;
    const float rho = predicted > noise ? actual / predicted : 1.0f;
    if (rho > 0.75f)
      st.mu = detail::clamp_mu(0.1f * st.mu);
    else if (rho < 0.25f)
      st.mu = detail::clamp_mu(4.0f * st.mu);
    return true;
  };

  for (int it = 0; it < P.nr_max_iter; ++it) {
    detail::linearise(M, kern, P, x0, U, cur->Y, s);
    build_system(P, m, n, y_ref, U, u_prev, s.G, *cur);
    r.iterations = uint8_t(it + 1);
    // J and g all finite: x * 0 is 0 for finite x, NaN otherwise
    float probe = cur->J * 0.0f;
NLSOFT_UNROLL(8)
    for (int a = 0; a < kk; ++a) probe += cur->g[a] * 0.0f;
    bool ok = probe == 0.0f;
    if (pending) {
      pending = false;
      if (!ok || !judge(cur->J)) {  // the step raised J: undo it, damp harder
        for (int a = 0; a < kk; ++a) U[a] = s.U_base[a];
        swap_systems();
        st.mu = detail::clamp_mu(10.0f * st.mu);
        r.flags |= kDamped;
        ok = true;
      }
    }
    if (!ok) {
      r.flags |= kNonFinite;
      break;
    }

    bool active[K];
    bool any_free = false, any_active = false;
    float hmax = 0.0f;
NLSOFT_UNROLL(8)
    for (int a = 0; a < kk; ++a) {
      active[a] = a >= k || (U[a] <= lo[a] && cur->g[a] > 0.0f) || (U[a] >= hi[a] && cur->g[a] < 0.0f);
      any_free = any_free || !active[a];
      any_active = any_active || active[a];
      const float d = cur->H[a * K + a];
      if (!active[a] && finite(d) && d > hmax) hmax = d;
    }
    if (!any_free) {  // every input pinned at a limit by the gradient: optimal as it is
      r.flags |= kConverged | kClamped;
      r.step = 0.0f;
      break;
    }
    const float hscale = hmax > 0.0f ? hmax : 1.0f;
    bool solved = false;
    for (int tries = 0; tries < 4 && !solved; ++tries) {
      solved = detail::damped_direction(*cur, kk, st.mu * hscale, active, any_active, s);
      if (!solved) {
        r.flags |= kSingular;
        st.mu = detail::clamp_mu(100.0f * (st.mu > 1e-4f ? st.mu : 1e-4f));
      }
    }
    if (!solved) break;

    // Take the step inside the limits; predict J's decrease from the model.
    float step = 0.0f, lin = 0.0f, quad = 0.0f;
    bool clamped = false;
NLSOFT_UNROLL(8)
    for (int a = 0; a < kk; ++a) {
      s.U_base[a] = U[a];
      const float want = U[a] + s.dU[a];
      U[a] = clamp_to(want, lo[a], hi[a]);
      clamped = clamped || U[a] != want;
      s.dU[a] = U[a] - s.U_base[a];
      step = std::fabs(s.dU[a]) > step ? std::fabs(s.dU[a]) : step;
    }
NLSOFT_UNROLL(8)
    for (int a = 0; a < kk; ++a) {  // dU' H dU over H's lower triangle (H is symmetric)
      lin += cur->g[a] * s.dU[a];
      float hd = 0.0f;
NLSOFT_UNROLL(8)
      for (int b = 0; b < a; ++b) hd += cur->H[a * K + b] * s.dU[b];
      quad += s.dU[a] * (2.0f * hd + cur->H[a * K + a] * s.dU[a]);
    }
    predicted = -(lin + 0.5f * quad);
    swap_systems();
    pending = true;
    r.step = step;
    if (clamped) r.flags |= kClamped;
    if (step < P.nr_tol) {
      r.flags |= kConverged;
      break;
    }
  }

  if (pending) {  // the last step, checked by one plain rollout
    kern.values(M, x0, U, P.N, P.Nc, s.constant, cur->Y, nullptr, s.roll);
    cur->J = cost_value(P, m, n, y_ref, U, u_prev, cur->Y);
    // Below the tolerance the comparison is rounding noise: keep the step.
    if (!judge(cur->J) && !(r.step < P.nr_tol)) {
      for (int a = 0; a < kk; ++a) U[a] = s.U_base[a];
      swap_systems();
      st.mu = detail::clamp_mu(10.0f * st.mu);
      r.flags |= kNoDescent;
      r.step = 0.0f;
    }
  }
  r.cost = cur->J;
  r.y_hat = cur->Y;
  if (kPadded)
NLSOFT_UNROLL(8)
    for (int a = 0; a < K; ++a)
      if (a < k) U_out[a] = U[a];
  return r;
}

}  // namespace nlsoft

NLSOFT_HOT_END
