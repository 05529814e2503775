// Simulated plants: what every plant offers and the pieces they share.
//
// The controller never sees these equations: it learns a forward model from
// logged (u, y, sensors) data (paper, "Problem Statement"). The plants are
// here so the whole loop can run without a rig: the host simulation, the
// posix firmware port and the tests.
//
// Every plant class P has the same shape (the plant registry relies on it; the
// generic plant, shared/plant_generic.hpp, has it with run-time m(), n(),
// w(), dt() from its spec):
//   static constexpr int m, n, w;       inputs, outputs, sensor channels
//   static constexpr float kDt;         the platform's control period, s
//   void reset(uint32_t seed);          initial state; seed drives the noise
//   void step(const float* u, float dt);  advance one control period with
//                                        input held (zero-order hold), u
//                                        clamped to the plant's limits
//   void output(float* y) const;        true end-effector output, n values
//                                        (m for msd, mm for hasel/tendon)
//   void sensors(float* l);             w noisy channels (draws noise)
//   static void input_limits(float* umin, float* umax);
//   static void neutral_input(float* u);
//   static void output_box(float* lo, float* hi);  bounds y never leaves
//   static constexpr DatasetScales kDataset;  how `dataset` excites it
//
// Guarantees for any input sequence: a non-finite input component acts as
// the neutral input, a non-finite or negative dt does not advance the state,
// dt above kMaxPlantDt is cut to it, every output and sensor value is finite.
#pragma once

#include <cmath>
#include <cstdint>

#include "shared/fixed_math.hpp"


namespace nlsoft {

// The largest plant SimPlant holds: a rig file's capacity (the generic
// plant, shared/plant_generic.hpp); the hand-written plants are smaller.
constexpr int kMaxPlantM = 8;
constexpr int kMaxPlantN = 6;
constexpr int kMaxPlantW = 32;

// How `dataset` excites a hand-written plant (app/model/excitation.cpp),
// chosen around its dominant time constant; seconds unless said. Host data:
// an image that never reads it carries none of it.
struct DatasetScales {
  double hold_min, hold_max;  // a level held this long
  double seg_min, seg_max;    // a segment of one kind of signal
  double f_min, f_max;        // Hz, the band a chirp sweeps
  double walk_tau;            // a random walk's smoothing
  double spread;              // half-width of levels around the common level, [0,1] units
  bool common_level;          // draw a common level for all inputs, or keep it central
  double dither;              // max dither amplitude, [0,1] units
  bool paper_input;           // segments of the paper's own input, u(t) = 1000 sin t cos t
};

// Longest period one step() call will integrate; guards against a stalled
// host loop asking for a huge catch-up step.
constexpr float kMaxPlantDt = 1.0f;

namespace plant_detail {

// The input the plant actually receives: clamped, NaN/Inf replaced by neutral.
inline float admit(float u, float lo, float hi, float neutral) {
  if (!std::isfinite(u)) return neutral;
  return u < lo ? lo : (u > hi ? hi : u);
}

// dt as the plant integrates it: 0 when unusable, at most kMaxPlantDt.
inline float admit_dt(float dt) {
  if (!std::isfinite(dt) || !(dt > 0.0f)) return 0.0f;
  return dt > kMaxPlantDt ? kMaxPlantDt : dt;
}

// Exact discretisation of a first-order lag x' = (target - x) / tau over dt
// with the target held: x += (1 - e^{-dt/tau}) (target - x). Stable for any dt.
inline float lag_gain(float dt, float tau) { return 1.0f - fixed_math::exp(-dt / tau); }

// Play (backlash) operator of half-width h: the output follows the input only
// once the input has moved h past it, so rising and falling sweeps differ by
// 2h. Rate independent, the simplest hysteresis with memory.
inline float play(float state, float input, float h) {
  if (state < input - h) return input - h;
  if (state > input + h) return input + h;
  return state;
}

inline float clampf(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

}  // namespace plant_detail

}  // namespace nlsoft
