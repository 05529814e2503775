// Mass-spring-damper, the paper's linear baseline (section "Mass-spring-damper",
// eq. 13):
//
//   x0' = x1
//   x1' = u - (k/m) x0 - (c/m) x1,      u = F_external / m  [N/kg]
//
// with k = 40 N/m, c = 0.5 N s/m, m = 0.1 kg, so omega0 = sqrt(k/m) = 20 rad/s
// and zeta = c / (2 sqrt(k m)) = 0.125. Output y = x0 in metres, no sensors.
//
// Integration: classical RK4 with the input held over the control period,
// cut into substeps of at most 0.25 ms (omega0 h <= 0.005, truncation error
// far below float rounding), the state summed with Kahan compensation, so
// the response matches the closed form to ~1e-6 m at metre scale.
#pragma once

#include <cmath>
#include <cstdint>

#include "shared/plant.hpp"
#include "shared/fixed_math.hpp"

namespace nlsoft {

class MsdPlant {
 public:
  static constexpr int m = 1, n = 1, w = 0;
  static constexpr float kDt = 1e-3f;  // 1 kHz (docs/platforms.md)
  // Around omega0 = 20 rad/s; with the paper's own input.
  static constexpr DatasetScales kDataset = {0.05, 2.0, 4.0, 20.0, 0.1, 8.0, 0.1, 0.35, false, 0.02, true};

  static constexpr float kStiffness = 40.0f;  // k, N/m
  static constexpr float kDamping = 0.5f;     // c, N s/m
  static constexpr float kMass = 0.1f;        // m, kg
  static constexpr float kUMax = 2000.0f;     // N/kg; the training signal peaks at 500
  static constexpr float kMaxSubstep = 2.5e-4f;

  // Worst case |x| under any admissible input: bang-bang forcing in phase with
  // the velocity settles at (u_max m / k) (1 + q) / (1 - q), where
  // q = exp(-zeta pi / sqrt(1 - zeta^2)) is the half-period decay: 25.6 m.
  static constexpr float kOutputBound = 26.0f;

  void reset(uint32_t /*seed*/ = 0) { set_state(0.0f, 0.0f); }
  void reseed_noise(uint32_t /*seed*/) {}  // noiseless

  void set_state(float position, float velocity) {
    x_ = std::isfinite(position) ? position : 0.0f;
    v_ = std::isfinite(velocity) ? velocity : 0.0f;
    x_carry_ = v_carry_ = 0.0f;
  }

  float position() const { return x_; }
  float velocity() const { return v_; }

  void step(const float* u, float dt) {
    const float a = plant_detail::admit(u != nullptr ? u[0] : 0.0f, -kUMax, kUMax, 0.0f);
    dt = plant_detail::admit_dt(dt);
    if (dt == 0.0f) return;
    // The 1e-4 keeps 1 ms at exactly 4 substeps despite rounding in dt.
    int substeps = static_cast<int>(std::ceil(dt / kMaxSubstep - 1e-4f));
    if (substeps < 1) substeps = 1;
    const float h = dt / static_cast<float>(substeps);
    for (int i = 0; i < substeps; ++i) rk4(a, h);
  }

  void output(float* y) const { y[0] = x_; }
  void sensors(float* /*l*/) {}

  static void input_limits(float* umin, float* umax) {
    umin[0] = -kUMax;
    umax[0] = kUMax;
  }
  static void neutral_input(float* u) { u[0] = 0.0f; }
  static void output_box(float* lo, float* hi) {
    lo[0] = -kOutputBound;
    hi[0] = kOutputBound;
  }

  // The paper's identification input u(t) = 1000 sin t cos t = 500 sin 2t N/kg.
  static float training_input(float t) { return 1000.0f * fixed_math::sin(t) * fixed_math::cos(t); }

 private:
  static constexpr float kK = kStiffness / kMass;  // 400 1/s^2
  static constexpr float kC = kDamping / kMass;    // 5 1/s

  static float accel(float u, float x, float v) { return u - kK * x - kC * v; }

  void rk4(float u, float h) {
    const float k1x = v_;
    const float k1v = accel(u, x_, v_);
    const float k2x = v_ + 0.5f * h * k1v;
    const float k2v = accel(u, x_ + 0.5f * h * k1x, k2x);
    const float k3x = v_ + 0.5f * h * k2v;
    const float k3v = accel(u, x_ + 0.5f * h * k2x, k3x);
    const float k4x = v_ + h * k3v;
    const float k4v = accel(u, x_ + h * k3x, k4x);
    accumulate(x_, x_carry_, (h / 6.0f) * (k1x + 2.0f * k2x + 2.0f * k3x + k4x));
    accumulate(v_, v_carry_, (h / 6.0f) * (k1v + 2.0f * k2v + 2.0f * k3v + k4v));
  }

  // Kahan-compensated sum: thousands of tiny increments per second onto a
  // metre-sized float state would otherwise lose ~1e-5 m to rounding.
  static void accumulate(float& sum, float& carry, float increment) {
    const float y = increment - carry;
    const float t = sum + y;
    carry = (t - sum) - y;
    sum = t;
  }

  float x_ = 0.0f;
  float v_ = 0.0f;
  float x_carry_ = 0.0f;
  float v_carry_ = 0.0f;
};

}  // namespace nlsoft
