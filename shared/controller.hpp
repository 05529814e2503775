#pragma once
// One control step of the paper's loop: build the input vector
// (Algorithm 1), solve for U by Newton-Raphson, apply u(k) = U_0, predict
// y_hat(k+1) for the next step's y-queue. All state is inside the object; its
// size is fixed by the capacity, nothing is allocated.
#include "shared/hot_path.hpp"
#include "shared/horizon.hpp"
#include "shared/input_vector.hpp"
#include "shared/newton.hpp"
#include "shared/params.hpp"

// What runs once per run or model, not per step: compiled for size
// (GCC's cold functions are), the step's own code for speed.
#define NLSOFT_COLD __attribute__((cold))

// The step is hot code too (see rollout.hpp): at -Os its per-value
// helpers (finite, the queue rolls) stay calls, ~600 instructions a step.
NLSOFT_HOT_BEGIN

namespace nlsoft {

template <class Cap>
struct StepResult {
  float u[Cap::m];                // applied input u(k), finite and inside limits
  float y_hat[Cap::N * Cap::n];   // predicted path y_hat(k+1 .. k+N) for the applied U
  float cost;                     // J at the applied U
  uint8_t iterations;
  uint8_t flags;                  // StepFlag bits
};

template <class Cap>
class Controller {
 public:
  static constexpr int K = Dims<Cap>::K;
  static constexpr int P = Dims<Cap>::p;

  // The model must already be finalized; params are validated here so a
  // controller can never run with a set the table would refuse.
  NLSOFT_COLD Status configure(const Model<Cap>* model, const Params<Cap>& params) {
    if (model == nullptr || model->layer_count == 0) return Status::BadFormat;
    const ParamResult ok = check_consistent(params, model->m);
    if (ok.status != Status::Ok) return ok.status;
    const Status k = select_kernels(*model, kernels_);
    if (k != Status::Ok) return k;
    model_ = model;
    params_ = params;
    return Status::Ok;
  }

  // Fills every history slot with a steady state: input u0, output y0, sensors l0.
  NLSOFT_COLD void reset(const float* u0, const float* y0, const float* l0) {
    const InputLayout L = layout();
    for (int j = 0; j < L.nd; ++j) push_input(x_, L, u0);
    for (int j = 0; j < L.dd; ++j) push_output(x_, L, y0);
    for (int i = 0; i < L.w; ++i) x_[L.l_begin() + i] = l0 ? l0[i] : 0.0f;
    for (int j = 0; j < L.n; ++j) y_next_[j] = y0[j];
    for (int a = 0; a < K; ++a) U_[a] = u0[a % L.m];
    solver_ = SolverState{};
  }

  // With no observer of y, start from the model's own rest: hold u0 and the
  // sensors l0 and let the prediction settle (the paper's "neutral point",
  // the Newton initial guess). Returns the settled y.
  NLSOFT_COLD const float* reset_at_rest(const float* u0, const float* l0, int iterations = 64) {
    const InputLayout L = layout();
    float y[Cap::n];
    for (int j = 0; j < L.n; ++j) y[j] = model_->out_offset()[j];
    reset(u0, y, l0);
    for (int it = 0; it < iterations; ++it) {
      const ConstantInputs c = kernels_.constant(*model_, x_, scratch_.pre);
      kernels_.values(*model_, x_, u0, 1, 1, c, y, nullptr, scratch_.roll);
      for (int j = 0; j < L.n; ++j)
        if (!finite(y[j])) y[j] = model_->out_offset()[j];
      push_input(x_, L, u0);
      push_output(x_, L, y);
    }
    reset(u0, y, l0);
    return y_next_;
  }

  // y_ref: the reference for y(k+1) ... y(k+N), N x n rows. sensors: l(k).
  // y_measured: y(k) when an observer exists (used if feedback = Measured).
  StepResult<Cap> step(const float* y_ref, const float* sensors, const float* y_measured) {
    const InputLayout L = layout();
    const Params<Cap>& Pm = params_;
    // Only what this step fills is initialised: value-initialising the whole
    // result would clear all Cap::N x Cap::n predicted values every step
    // (768 floats on the host, 1 % of a hasel step), of which N x n are used;
    // on the M4F newlib-nano's memset does it byte by byte.
    StepResult<Cap> out;
    out.flags = 0;

    // Algorithm 1, lines 3-5: newest output and sensor signals into x.
    const float* y_now = y_next_;
    if (Pm.feedback == Feedback::Measured && y_measured && all_finite(y_measured, L.n)) y_now = y_measured;
    push_output(x_, L, y_now);
    // Copied whole when all are finite (the usual case: one test for all),
    // else value by value: a non-finite sensor value keeps the previous one.
    float* const l = x_ + L.l_begin();
    if (sensors && all_finite(sensors, L.w)) {
      for (int i = 0; i < L.w; ++i) l[i] = sensors[i];
    } else {
      for (int i = 0; i < L.w; ++i) {
        if (sensors && finite(sensors[i]))
          l[i] = sensors[i];
        else
          out.flags |= kBadSensor;
      }
    }
    // A non-finite reference point is held at the current output.
    const int refs = Pm.N * L.n;
    float probe = 0.0f;  // copied and tested for finiteness in one pass: see all_finite
    for (int r = 0; r < refs; ++r) {
      ref_[r] = y_ref[r];
      probe += y_ref[r] * 0.0f;
    }
    if (!(probe == 0.0f)) {
      for (int t = 0; t < Pm.N; ++t)
        for (int j = 0; j < L.n; ++j) {
          const float v = y_ref[t * L.n + j];
          if (finite(v)) {
            ref_[t * L.n + j] = v;
          } else {
            ref_[t * L.n + j] = y_now[j];
            out.flags |= kBadReference;
          }
        }
    }

    const NewtonResult nr = newton_solve(*model_, kernels_, Pm, x_, ref_, U_, solver_, scratch_);
    out.iterations = nr.iterations;
    out.flags |= nr.flags;
    // Predicted path and cost at the U actually applied.
    for (int r = 0; r < refs; ++r) out.y_hat[r] = nr.y_hat[r];
    out.cost = nr.cost;

    // Algorithm 1, lines 1-2: u(k) = U_0 into the u-queue.
    for (int i = 0; i < L.m; ++i) out.u[i] = clamp_to(U_[i], Pm.u_min[i], Pm.u_max[i]);
    push_input(x_, L, out.u);
    for (int j = 0; j < L.n; ++j) y_next_[j] = finite(out.y_hat[j]) ? out.y_hat[j] : y_now[j];

    // Warm start: shift U one step, repeat the last row.
    for (int j = 0; j + 1 < Pm.Nc && j + 1 < Cap::Nc; ++j)
      for (int i = 0; i < L.m; ++i) U_[j * L.m + i] = U_[(j + 1) * L.m + i];
    return out;
  }

  const Params<Cap>& params() const { return params_; }
  // Parameter writes go through the table (atomic, validated).
  ParamResult set_param(ParamId id, const float* v, int count) {
    const int n_old_nc = params_.Nc;
    const ParamResult r = nlsoft::set_param(params_, id, v, count, model_->m, model_->n);
    if (r.status == Status::Ok && params_.Nc > n_old_nc) {
      // added control rows start from the last planned input
      for (int j = n_old_nc; j < params_.Nc; ++j)
        for (int i = 0; i < model_->m; ++i) U_[j * model_->m + i] = U_[(n_old_nc - 1) * model_->m + i];
    }
    return r;
  }
  const float* input_vector() const { return x_; }
  const Model<Cap>& model() const { return *model_; }

 private:
  // An image's capacity runs one shape, its model's (kernels.hpp refuses
  // others): the layout is that shape's constants, and the step's loops
  // over m, n and w have fixed trip counts.
  template <class... S>
  static constexpr bool one_shape(ShapeList<S...>) {
    return !Cap::generic && sizeof...(S) == 1;
  }
  template <class S>
  static constexpr InputLayout shape_layout(ShapeList<S>) {
    return InputLayout{S::m, S::n, S::w, S::nd, S::nd};
  }
  InputLayout layout() const {
    if constexpr (one_shape(typename Cap::Shapes{}))
      return shape_layout(typename Cap::Shapes{});
    else
      return layout_of(*model_);
  }
  // x * 0 is 0 for a finite x and NaN otherwise: one test for all c values
  static bool all_finite(const float* v, int c) {
    float probe = 0.0f;
    for (int i = 0; i < c; ++i) probe += v[i] * 0.0f;
    return probe == 0.0f;
  }

  const Model<Cap>* model_ = nullptr;
  RolloutKernels<Cap> kernels_{};
  Params<Cap> params_{};
  float x_[P] = {};
  float U_[K] = {};
  float y_next_[Cap::n] = {};
  float ref_[Cap::N * Cap::n] = {};
  SolverState solver_{};
  SolverScratch<Cap> scratch_{};
};

}  // namespace nlsoft

NLSOFT_HOT_END
