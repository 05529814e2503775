// Tendon-driven soft body surrogate (paper, "Tendon-based platform": a soft
// 3D-printed mesh pulled by two servos through Kevlar tendons, eleven
// LightLace optical channels; task space 40.4 x 28.3 x 35.0 mm, a curved
// hull; control at 120 Hz).
//
// Per servo i = 0..1, command u_i in [-1.2, 1.2] rad from the datum:
//   servo   theta_i += (1 - exp(-dt/tau)) (u_i - theta_i),  tau = 50 ms
//   slack   q_i = play(q_i, theta_i, b),  b = 0.04 rad (tendon slack, 3.3 %
//           of the range: the body does not move until the slack is taken up)
//   bend    alpha_i = a_max tanh(q_i / q_s),  a_max = 1.3 rad, q_s = 1 rad
//           (the mesh stiffens as it bends)
// Servo 0 (horizontal) bends left-right, servo 1 (vertical) up-down. The tip
// of the bent body, in mm from its neutral position:
//   y1 = rho1 sin(alpha_0) cos(0.35 alpha_1)                 left-right
//   y2 = rho2 sin(alpha_1) - g (1 - cos alpha_0)              up-down, sagging
//                                                            when bent aside
//   y0 = D (1 - cos alpha_0 cos alpha_1)                     depth
// rho1 = 16, rho2 = 19, g = 2, D = 48 mm. With two inputs and three outputs
// the tip lives on a surface: y0 is a bowl over (y1, y2), about
//   y0 ~ (D/2) ((y1/rho1)^2 + (y2/rho2)^2),
// so y0 is never commanded independently (the paper weights it 1e-3 in Q).
// Reachable (|alpha| <= 1.067): y1 in [-14.0, 14.0], y2 in [-17.7, 16.6],
// y0 in [0, 36.8] mm, inside the box y0 in [-1.7, 38.7], y1 in [-14.15, 14.15],
// y2 in [-17.95, 17.05] (40.4 x 28.3 x 35.0). Neutral u = 0 gives (0, 0, 0).
//
// Infinity fits the bowl when A ~ D C^2 / (2 rho2^2) = 0.066 C^2 and B is
// moderate: kInfinity{A, B, C} = {10, 16, 12} mm with centre (0, 0, 0) keeps
// |y1| <= 8 and |y2| <= 12 mm, well inside the reachable set; y0 then follows
// the reference to within the y1 part of the bowl (<= 6.3 mm). Pringle and
// Diagonal: B = 12, C = 12, A = 4, same centre.
//
// Sensors: eleven LightLace channels, fibre j running at angle
// psi_j = 2 pi j / 11 through the mesh; light transmitted falls off with the
// square of the fibre's bend,
//   l_j = exp(-k_j (o_j + 0.8 (alpha_0 cos psi_j + alpha_1 sin psi_j))^2),
// o_j = 0.4 + 0.05 j, k_j = 0.6 + 0.04 j, normalised to [0, 1], plus Gaussian
// noise sigma = 0.01 from the seeded Rng (then clipped to [0, 1], as the
// normalised ADC reading is).
#pragma once

#include <cmath>
#include <cstdint>

#include "shared/plant.hpp"
#include "shared/fixed_math.hpp"
#include "shared/rng.hpp"

namespace nlsoft {

class TendonPlant {
 public:
  static constexpr int m = 2, n = 3, w = 11;
  static constexpr float kDt = 1.0f / 120.0f;
  // Around the 50 ms servo.
  static constexpr DatasetScales kDataset = {0.04, 1.2, 3.0, 15.0, 0.05, 3.0, 0.2, 0.5, false, 0.03, false};

  static constexpr float kUMax = 1.2f;     // rad
  static constexpr float kTau = 0.05f;     // s, servo
  static constexpr float kSlack = 0.04f;   // rad, b
  static constexpr float kBendMax = 1.3f;  // rad, a_max
  static constexpr float kBendSoft = 1.0f; // rad, q_s
  static constexpr float kRho1 = 16.0f;    // mm
  static constexpr float kRho2 = 19.0f;    // mm
  static constexpr float kSag = 2.0f;      // mm, g
  static constexpr float kDepth = 48.0f;   // mm, D
  static constexpr float kNoise = 0.01f;

  static constexpr float kInfinity[3] = {10.0f, 16.0f, 12.0f};  // A, B, C
  static constexpr float kPringle[3] = {4.0f, 12.0f, 12.0f};   // A, B, C
  static constexpr float kCentre[3] = {0.0f, 0.0f, 0.0f};

  void reseed_noise(uint32_t seed) { rng_.reseed(seed); }
  void reset(uint32_t seed = 0) {
    rng_.reseed(seed);
    for (int i = 0; i < m; ++i) theta_[i] = q_[i] = 0.0f;
  }

  void step(const float* u, float dt) {
    dt = plant_detail::admit_dt(dt);
    const float gain = plant_detail::lag_gain(dt, kTau);
    for (int i = 0; i < m; ++i) {
      const float ui = plant_detail::admit(u != nullptr ? u[i] : 0.0f, -kUMax, kUMax, 0.0f);
      theta_[i] += gain * (ui - theta_[i]);
      q_[i] = plant_detail::play(q_[i], theta_[i], kSlack);
    }
  }

  void output(float* y) const {
    const float a0 = bend(0);
    const float a1 = bend(1);
    y[1] = kRho1 * fixed_math::sin(a0) * fixed_math::cos(0.35f * a1);
    y[2] = kRho2 * fixed_math::sin(a1) - kSag * (1.0f - fixed_math::cos(a0));
    y[0] = kDepth * (1.0f - fixed_math::cos(a0) * fixed_math::cos(a1));
  }

  void sensors(float* l) {
    const float a0 = bend(0);
    const float a1 = bend(1);
    for (int j = 0; j < w; ++j) {
      const float psi = kTwoPi * static_cast<float>(j) / static_cast<float>(w);
      const float o = 0.4f + 0.05f * static_cast<float>(j);
      const float k = 0.6f + 0.04f * static_cast<float>(j);
      const float s = o + 0.8f * (a0 * fixed_math::cos(psi) + a1 * fixed_math::sin(psi));
      const float v = fixed_math::exp(-k * s * s) + kNoise * rng_.gaussian();
      l[j] = plant_detail::clampf(v, 0.0f, 1.0f);
    }
  }

  static void input_limits(float* umin, float* umax) {
    for (int i = 0; i < m; ++i) {
      umin[i] = -kUMax;
      umax[i] = kUMax;
    }
  }
  static void neutral_input(float* u) {
    for (int i = 0; i < m; ++i) u[i] = 0.0f;
  }
  static void output_box(float* lo, float* hi) {
    lo[0] = -1.7f;
    hi[0] = 38.7f;
    lo[1] = -14.15f;
    hi[1] = 14.15f;
    lo[2] = -17.95f;
    hi[2] = 17.05f;
  }

  // Bend angles alpha_i (state; for tests and plots).
  float bend(int i) const { return kBendMax * fixed_math::tanh(q_[i] / kBendSoft); }
  float servo_angle(int i) const { return theta_[i]; }

 private:
  static constexpr float kTwoPi = 6.28318530717958647692f;

  float theta_[m] = {0.0f, 0.0f};
  float q_[m] = {0.0f, 0.0f};
  Rng rng_{0};
};

}  // namespace nlsoft
