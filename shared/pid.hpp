// Discrete PID, the paper's baseline ("Mass-spring-damper" results: "PID
// controller that uses robust tuning"). Its gains are a rig's ([pid] in a
// rig file, docs/rig-file.md; rigs/msd.toml holds the paper's).
//
// Per axis, with e = r - y and sample period dt:
//   P = Kp e
//   I += Ki e dt                  only while that does not push a saturated
//                                 output further (conditional integration,
//                                 the anti-windup)
//   D = Kd d,  d = lowpass(-(y - y_prev) / dt, tau_d)
//                                 derivative on the measurement, so a
//                                 reference step gives no derivative kick
//   u = clamp(s (P + I + D), umin, umax)
//
// The output scale s maps the PID's units to the plant input.
//
// Finite output guarantee: a non-finite reference, measurement or dt leaves
// the state untouched and repeats the last (clamped) output; a non-finite
// intermediate resets that axis's integrator and does the same.
#pragma once

#include <cmath>

namespace nlsoft {

constexpr int kPidMaxAxes = 8;

struct PidGains {
  float kp, ki, kd;
};

class Pid {
 public:
  // Sets the axis count, gains, output scale, derivative filter time
  // constant (s, 0 = unfiltered) and output limits, and resets the state.
  // Returns false and changes nothing when a value is unusable (axes outside
  // 1..kPidMaxAxes, non-finite or negative gains, zero or non-finite scale,
  // negative tau, umin > umax).
  bool configure(int axes, const PidGains& gains, const float* umin, const float* umax,
                 float output_scale = 1.0f, float d_filter_tau = 0.0f) {
    if (axes < 1 || axes > kPidMaxAxes || umin == nullptr || umax == nullptr) return false;
    if (!finite_nonneg(gains.kp) || !finite_nonneg(gains.ki) || !finite_nonneg(gains.kd))
      return false;
    if (!std::isfinite(output_scale) || output_scale == 0.0f) return false;
    if (!finite_nonneg(d_filter_tau)) return false;
    for (int i = 0; i < axes; ++i)
      if (!std::isfinite(umin[i]) || !std::isfinite(umax[i]) || umin[i] > umax[i]) return false;
    axes_ = axes;
    gains_ = gains;
    scale_ = output_scale;
    tau_ = d_filter_tau;
    for (int i = 0; i < axes; ++i) {
      umin_[i] = umin[i];
      umax_[i] = umax[i];
    }
    reset();
    return true;
  }

  // Clears integrators and derivative memory; the next output starts from
  // zero integral action as at power-up.
  void reset() {
    for (int i = 0; i < kPidMaxAxes; ++i) {
      integral_[i] = 0.0f;
      y_prev_[i] = 0.0f;
      d_filt_[i] = 0.0f;
      u_prev_[i] = 0.0f;
      primed_[i] = false;
    }
    for (int i = 0; i < axes_; ++i) u_prev_[i] = clamp_axis(i, 0.0f);
  }

  int axes() const { return axes_; }
  const PidGains& gains() const { return gains_; }
  float integral(int axis) const { return integral_[axis]; }

  // One control step: ref and y hold axes() values, u receives axes() values.
  void step(const float* ref, const float* y, float dt, float* u) {
    const bool dt_ok = std::isfinite(dt) && dt > 0.0f;
    for (int i = 0; i < axes_; ++i) {
      if (!dt_ok || !std::isfinite(ref[i]) || !std::isfinite(y[i])) {
        u[i] = u_prev_[i];
        continue;
      }
      const float e = ref[i] - y[i];
      float d_raw = primed_[i] ? -(y[i] - y_prev_[i]) / dt : 0.0f;
      if (!std::isfinite(d_raw)) d_raw = 0.0f;
      const float alpha = dt / (tau_ + dt);
      const float d = d_filt_[i] + alpha * (d_raw - d_filt_[i]);
      const float p_term = gains_.kp * e;
      const float d_term = gains_.kd * d;
      const float i_next = integral_[i] + gains_.ki * e * dt;
      // Integrate unless the output is already pinned and e pushes it further.
      const float trial = scale_ * (p_term + i_next + d_term);
      const bool push_high = trial > umax_[i] && scale_ * e > 0.0f;
      const bool push_low = trial < umin_[i] && scale_ * e < 0.0f;
      const float integral = (push_high || push_low) ? integral_[i] : i_next;
      const float raw = scale_ * (p_term + integral + d_term);
      if (!std::isfinite(raw)) {
        integral_[i] = 0.0f;
        d_filt_[i] = 0.0f;
        y_prev_[i] = y[i];
        primed_[i] = true;
        u[i] = u_prev_[i];
        continue;
      }
      integral_[i] = integral;
      d_filt_[i] = d;
      y_prev_[i] = y[i];
      primed_[i] = true;
      u[i] = u_prev_[i] = clamp_axis(i, raw);
    }
  }

 private:
  static bool finite_nonneg(float v) { return std::isfinite(v) && v >= 0.0f; }

  float clamp_axis(int i, float v) const {
    return v < umin_[i] ? umin_[i] : (v > umax_[i] ? umax_[i] : v);
  }

  int axes_ = 1;
  PidGains gains_{};
  float scale_ = 1.0f;
  float tau_ = 0.0f;
  float umin_[kPidMaxAxes] = {-1.0f};
  float umax_[kPidMaxAxes] = {1.0f};
  float integral_[kPidMaxAxes] = {};
  float y_prev_[kPidMaxAxes] = {};
  float d_filt_[kPidMaxAxes] = {};
  float u_prev_[kPidMaxAxes] = {};
  bool primed_[kPidMaxAxes] = {};  // y_prev_ holds a real sample
};

}  // namespace nlsoft
