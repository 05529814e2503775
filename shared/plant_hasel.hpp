// HASEL tilting platform surrogate (paper, "HASEL-based platform": six folded
// HASELs with magnetic sensors under an acrylic plate carrying the marker;
// task space 23.0 x 20.2 x 19.2 mm, control at 130 Hz).
//
// Per actuator i = 0..5, drive u_i in [0, 1] (normalised 0-8 kV):
//   hysteresis  p_i = play(p_i, u_i, h),  h = 0.03       (dead band 2h)
//               s_i = (p_i - h) / (1 - 2h)                (back to [0, 1])
//   statics     e*_i = 0.3 s + 0.7 (3 s^2 - 2 s^3)         (electrostatic
//               zipping: slow start, steep middle, saturating end)
//   lag         e_i += (1 - exp(-dt/tau)) (e*_i - e_i),  tau = 25 ms rising
//               (charging), 45 ms falling (draining optocoupler is slower)
// e_i in [0, 1] is the normalised extension of HASEL i.
//
// Platform (actuators at phi_i = 60 i deg): the plate's least-squares plane
// has mean height e_bar = mean(e) and slopes
//   t_x = (1/3) sum e_i cos phi_i,  t_y = (1/3) sum e_i sin phi_i,
// tilting it by theta_x = kappa t_x, theta_y = kappa t_y. The marker stands H
// above the plate, so the end effector is
//   x = H sin theta_x
//   y = H sin theta_y cos theta_x
//   z = z0 + Z e_bar - H (1 - cos theta_x cos theta_y)
// with kappa = 0.85, H = 21 mm, Z = 18.6 mm, z0 = 0.3 mm. Reachable:
// |x| <= 11.27, |y| <= 9.90, z in [0.3, 18.9] mm, inside the 23.0 x 20.2 x 19.2
// box x in [-11.5, 11.5], y in [-10.1, 10.1], z in [0, 19.2]. Neutral u = 0.5
// gives (0, 0, 9.6), the centre of the box.
//
// Sensors: under each HASEL a 3-axis magnetometer reads the field of all six
// magnet blocks (point dipoles along the plate normal, gap G0 + S e_k above
// the sensor plane, shifted sideways by the tilt), 1/r^3 fall-off with
// cross-talk from the neighbours, each magnetometer's axes turned to face
// outwards, scaled so the own magnet's B_z is 2 at zero extension; channel
// 3j + a is sensor j, axis a. Gaussian noise sigma = 0.01 (about 0.6 % of the
// B_z range) from the seeded Rng.
//
// Swirl: at its own size (scale 1) and centre (0, 0, 4.0) mm the whole path
// (x -5.7..7.5, y -6.6..4.8, z 4.0..8.3 mm) is reachable with every actuator
// kept at least 13 % of its range away from either end (the tightest points
// are the rest point, low, and the outer turn, tilted most); the reset pose
// (0, 0, 9.6) is 5.6 mm above the start. tests/shared/test_plants.cpp checks
// the fit. Scales up to about 1.2 still fit with this centre.
#pragma once

#include <cmath>
#include <cstdint>

#include "shared/plant.hpp"
#include "shared/fixed_math.hpp"
#include "shared/rng.hpp"

namespace nlsoft {

class HaselPlant {
 public:
  static constexpr int m = 6, n = 3, w = 18;
  static constexpr float kDt = 1.0f / 130.0f;
  // Around the 25-45 ms lag; the six actuators share a common level (the plate's height).
  static constexpr DatasetScales kDataset = {0.04, 1.2, 3.0, 15.0, 0.05, 4.0, 0.15, 0.6, true, 0.03, false};

  static constexpr float kPlay = 0.03f;     // h
  static constexpr float kTauUp = 0.025f;   // s
  static constexpr float kTauDown = 0.045f; // s
  static constexpr float kKappa = 0.85f;    // rad per unit slope
  static constexpr float kHeight = 21.0f;   // H, mm
  static constexpr float kStroke = 18.6f;   // Z, mm
  static constexpr float kZ0 = 0.3f;        // mm
  static constexpr float kNoise = 0.01f;    // sensor sigma

  static constexpr float kSwirlScale = 1.0f;
  static constexpr float kSwirlCentre[3] = {0.0f, 0.0f, 4.0f};

  void reseed_noise(uint32_t seed) { rng_.reseed(seed); }
  void reset(uint32_t seed = 0) {
    rng_.reseed(seed);
    for (int i = 0; i < m; ++i) {
      play_[i] = 0.5f;
      e_[i] = statics(0.5f);
    }
  }

  void step(const float* u, float dt) {
    dt = plant_detail::admit_dt(dt);
    const float gain_up = plant_detail::lag_gain(dt, kTauUp);
    const float gain_down = plant_detail::lag_gain(dt, kTauDown);
    for (int i = 0; i < m; ++i) {
      const float ui = plant_detail::admit(u != nullptr ? u[i] : 0.5f, 0.0f, 1.0f, 0.5f);
      play_[i] = plant_detail::play(play_[i], ui, kPlay);
      const float s = plant_detail::clampf((play_[i] - kPlay) / (1.0f - 2.0f * kPlay), 0.0f, 1.0f);
      const float target = statics(s);
      e_[i] += (target > e_[i] ? gain_up : gain_down) * (target - e_[i]);
      e_[i] = plant_detail::clampf(e_[i], 0.0f, 1.0f);
    }
  }

  void output(float* y) const {
    float tx, ty, mean;
    pose(tx, ty, mean);
    const float ax = kKappa * tx;
    const float ay = kKappa * ty;
    y[0] = kHeight * fixed_math::sin(ax);
    y[1] = kHeight * fixed_math::sin(ay) * fixed_math::cos(ax);
    y[2] = kZ0 + kStroke * mean - kHeight * (1.0f - fixed_math::cos(ax) * fixed_math::cos(ay));
  }

  void sensors(float* l) {
    float tx, ty, mean;
    pose(tx, ty, mean);
    const float ax = kKappa * tx;
    const float ay = kKappa * ty;
    // The magnets ride on the plate: their axis is the plate normal and the
    // tilt slides them sideways relative to the sensors fixed to the base.
    float nx = fixed_math::sin(ax), ny = fixed_math::sin(ay), nz = fixed_math::cos(ax) * fixed_math::cos(ay);
    const float nn = 1.0f / std::sqrt(nx * nx + ny * ny + nz * nz);
    nx *= nn;
    ny *= nn;
    nz *= nn;
    const float shift_x = kSlide * fixed_math::sin(ax);
    const float shift_y = kSlide * fixed_math::sin(ay);
    for (int j = 0; j < m; ++j) {
      float b[3] = {0.0f, 0.0f, 0.0f};
      for (int k = 0; k < m; ++k) {
        // r: from magnet k to sensor j
        const float rx = kSensorRadius * (kCos[j] - kCos[k]) - shift_x;
        const float ry = kSensorRadius * (kSin[j] - kSin[k]) - shift_y;
        const float rz = -(kGap + kGapStroke * e_[k]);
        const float r2 = rx * rx + ry * ry + rz * rz;
        const float inv_r = 1.0f / std::sqrt(r2);
        const float inv_r3 = inv_r * inv_r * inv_r;
        const float mr = (nx * rx + ny * ry + nz * rz) * inv_r;  // m . r_hat
        b[0] += (3.0f * mr * rx * inv_r - nx) * inv_r3;
        b[1] += (3.0f * mr * ry * inv_r - ny) * inv_r3;
        b[2] += (3.0f * mr * rz * inv_r - nz) * inv_r3;
      }
      // Sensor axes turned by phi_j; scale G0^3 makes the own B_z 2 at e = 0
      // (a dipole's on-axis field is 2 m / r^3).
      const float s = kGap * kGap * kGap;
      const float bx = kCos[j] * b[0] + kSin[j] * b[1];
      const float by = -kSin[j] * b[0] + kCos[j] * b[1];
      l[3 * j + 0] = s * bx + kNoise * rng_.gaussian();
      l[3 * j + 1] = s * by + kNoise * rng_.gaussian();
      l[3 * j + 2] = s * b[2] + kNoise * rng_.gaussian();
    }
  }

  static void input_limits(float* umin, float* umax) {
    for (int i = 0; i < m; ++i) {
      umin[i] = 0.0f;
      umax[i] = 1.0f;
    }
  }
  static void neutral_input(float* u) {
    for (int i = 0; i < m; ++i) u[i] = 0.5f;
  }
  static void output_box(float* lo, float* hi) {
    lo[0] = -11.5f;
    hi[0] = 11.5f;
    lo[1] = -10.1f;
    hi[1] = 10.1f;
    lo[2] = 0.0f;
    hi[2] = 19.2f;
  }

  // Normalised extensions e_i (state; for tests and plots).
  float extension(int i) const { return e_[i]; }

  // Static input -> extension map e* = 0.3 s + 0.7 (3 s^2 - 2 s^3).
  static float statics(float s) { return 0.3f * s + 0.7f * s * s * (3.0f - 2.0f * s); }

 private:
  static constexpr float kSensorRadius = 15.0f;  // mm, sensors on a circle
  static constexpr float kGap = 5.0f;            // G0, mm at zero extension
  static constexpr float kGapStroke = 4.0f;      // S, mm at full extension
  static constexpr float kSlide = 3.0f;          // mm of sideways slide per unit sin(tilt)
  static constexpr float kCos[6] = {1.0f, 0.5f, -0.5f, -1.0f, -0.5f, 0.5f};
  static constexpr float kSin[6] = {0.0f,        0.86602540378f,  0.86602540378f,
                                    0.0f,        -0.86602540378f, -0.86602540378f};

  void pose(float& tx, float& ty, float& mean) const {
    tx = ty = mean = 0.0f;
    for (int i = 0; i < m; ++i) {
      tx += e_[i] * kCos[i];
      ty += e_[i] * kSin[i];
      mean += e_[i];
    }
    tx *= (1.0f / 3.0f);
    ty *= (1.0f / 3.0f);
    mean *= (1.0f / 6.0f);
  }

  float play_[m] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
  float e_[m] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
  Rng rng_{0};
};

}  // namespace nlsoft
