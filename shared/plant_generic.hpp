// A soft-actuator plant whose every constant is data: the stand-in for a rig
// the code was never compiled for (a rig file's `[plant] kind = "generic"`,
// docs/rig-file.md), and what a HIL image embeds as a constexpr spec.
//
// The model follows the paper's soft rigs (hasel, tendon: shared/plant_*.hpp)
// with their particular geometry replaced by matrices. Per input i = 0..m-1:
//   admit       u_i clamped to [min_i, max_i]; NaN/Inf acts as neutral_i
//   hysteresis  p_i = play(p_i, u_i, play_i)          (rising and falling
//               sweeps differ by 2 play_i; p_i starts at neutral_i)
//   statics     s_i = shape_i(p_i - neutral_i) * gain_i, with shape
//                 linear      d
//                 tanh        knee tanh(d / knee)     (soft saturation)
//                 saturation  clamp(d, -knee, knee)   (hard stop)
//                 power       sign(d) |d|^exponent    (stiffening / zipping)
//   lag         a_i += (1 - exp(-dt/tau_i)) (s_i - a_i)   (tau_i = 0: a_i = s_i)
// a_i is the actuator's internal state, zero at neutral. Per output j:
//   coupling    y*_j = offset_j + sum_i B[j][i] a_i
//   lag         y_j += (1 - exp(-dt/tau_j)) (y*_j - y_j)  (tau_j = 0: y_j = y*_j)
//   box         y_j clamped to [lo_j, hi_j]           (where the output can be)
// Per sensor channel k, from the internal state x = [a_0..a_{m-1}, y_0..y_{n-1}]:
//   l_k = offset_k + sum_c C[k][c] x_c + noise_k * N(0, 1)   (seeded Rng)
//
// A constant input held long enough gives the static map
// y = clamp(offset + B s(p)), p the play operator's settled value (u itself
// when play = 0; static_output() computes it for a step from rest). reset() starts the plant at rest at the
// neutral input: a = 0, y = clamp(offset).
//
// Same interface and guarantees as the other plants (shared/plant.hpp), with
// run-time dimensions: m(), n(), w(), dt() instead of constants (FixedGenericPlant,
// below, has them as constants from a constexpr spec). A spec that
// generic_spec_problem() refuses is not taken (configure returns false and
// the plant keeps its previous spec). No heap, no exceptions, float.
#pragma once

#include <cmath>
#include <cstdint>

#include "shared/plant.hpp"
#include "shared/fixed_math.hpp"
#include "shared/rng.hpp"

namespace nlsoft {

// What a generic plant may describe: a rig file's own capacity.
constexpr int kGenericMaxM = 8;
constexpr int kGenericMaxN = 6;
constexpr int kGenericMaxW = 32;

enum class GenericShape : uint8_t { Linear = 0, Tanh = 1, Saturation = 2, Power = 3 };

// Each shape as a rig file's `shape` names it, indexed by GenericShape.
struct GenericShapeName {
  GenericShape shape;
  const char* name;
};
inline constexpr GenericShapeName kGenericShapes[] = {{GenericShape::Linear, "linear"},
                                                      {GenericShape::Tanh, "tanh"},
                                                      {GenericShape::Saturation, "saturation"},
                                                      {GenericShape::Power, "power"}};
static_assert(kGenericShapes[3].shape == GenericShape::Power, "kGenericShapes is indexed by GenericShape");
constexpr const char* generic_shape_name(GenericShape s) { return kGenericShapes[uint8_t(s)].name; }

struct GenericInputSpec {
  float min = 0.0f, max = 1.0f, neutral = 0.0f;  // input units
  float gain = 1.0f;                             // actuator state per shaped input unit
  GenericShape shape = GenericShape::Linear;
  float knee = 1.0f;      // tanh, saturation: input units from neutral where it bends (> 0)
  float exponent = 1.0f;  // power: (0, 8]
  float play = 0.0f;      // hysteresis half-width, input units (>= 0)
  float tau = 0.0f;       // lag time constant, s (>= 0; 0: none)
};

struct GenericOutputSpec {
  float lo = -1.0f, hi = 1.0f;  // the box y never leaves
  float offset = 0.0f;          // y* at every actuator state 0
  float tau = 0.0f;             // lag time constant, s (>= 0; 0: none)
};

struct GenericSensorSpec {
  float offset = 0.0f;
  float noise = 0.0f;  // Gaussian sigma (>= 0)
};

// POD: a firmware image holds one as a constexpr, the console fills one from
// a rig file (host/rig/rig_plant.cpp). About 2.5 kB.
struct GenericPlantSpec {
  uint8_t m = 1, n = 1, w = 0;
  float dt = 0.01f;  // the control period, s
  GenericInputSpec input[kGenericMaxM] = {};
  GenericOutputSpec output[kGenericMaxN] = {};
  GenericSensorSpec sensor[kGenericMaxW] = {};
  float B[kGenericMaxN][kGenericMaxM] = {};                 // outputs from actuator states
  float C[kGenericMaxW][kGenericMaxM + kGenericMaxN] = {};  // sensors from [a, y]
};

namespace generic_detail {

// std::isfinite is not constexpr in C++17, and a HIL image checks its
// embedded spec at compile time (FixedGenericPlant): comparisons alone.
constexpr bool finite(float v) { return v == v && v <= 3.40282347e38f && v >= -3.40282347e38f; }

constexpr bool finite_all(const float* v, int count) {
  for (int i = 0; i < count; ++i)
    if (!finite(v[i])) return false;
  return true;
}

// The shaped deviation from neutral, before the gain.
inline float shape(const GenericInputSpec& s, float d) {
  switch (s.shape) {
    case GenericShape::Tanh: return s.knee * fixed_math::tanh(d / s.knee);
    case GenericShape::Saturation: return plant_detail::clampf(d, -s.knee, s.knee);
    case GenericShape::Power: {
      const float mag = fixed_math::pow(std::fabs(d), s.exponent);
      return d < 0.0f ? -mag : mag;
    }
    case GenericShape::Linear:
    default: return d;
  }
}

}  // namespace generic_detail

// Why `s` cannot run, or nullptr when it can. The rig loader names the key
// of each fault itself; this is the plant's own guard (and a firmware's
// static check of its embedded spec).
constexpr const char* generic_spec_problem(const GenericPlantSpec& s) {
  if (s.m < 1 || s.m > kGenericMaxM) return "m must be 1..8";
  if (s.n < 1 || s.n > kGenericMaxN) return "n must be 1..6";
  if (s.w > kGenericMaxW) return "w must be 0..32";
  if (!generic_detail::finite(s.dt) || !(s.dt > 0.0f) || s.dt > kMaxPlantDt) return "dt must be in (0, 1] s";
  for (int i = 0; i < s.m; ++i) {
    const GenericInputSpec& in = s.input[i];
    const float v[] = {in.min, in.max, in.neutral, in.gain, in.knee, in.exponent, in.play, in.tau};
    if (!generic_detail::finite_all(v, 8)) return "an input value is not finite";
    if (!(in.min < in.max)) return "an input's min must be < max";
    if (in.neutral < in.min || in.neutral > in.max) return "an input's neutral must lie in [min, max]";
    if (uint8_t(in.shape) > uint8_t(GenericShape::Power)) return "unknown input shape";
    if (!(in.knee > 0.0f)) return "an input's knee must be > 0";
    if (!(in.exponent > 0.0f) || in.exponent > 8.0f) return "an input's exponent must be in (0, 8]";
    if (in.play < 0.0f) return "an input's play must be >= 0";
    if (in.tau < 0.0f) return "an input's time constant must be >= 0";
  }
  for (int j = 0; j < s.n; ++j) {
    const GenericOutputSpec& out = s.output[j];
    const float v[] = {out.lo, out.hi, out.offset, out.tau};
    if (!generic_detail::finite_all(v, 4)) return "an output value is not finite";
    if (!(out.lo < out.hi)) return "an output's lo must be < hi";
    if (out.tau < 0.0f) return "an output's time constant must be >= 0";
    if (!generic_detail::finite_all(s.B[j], s.m)) return "a coupling value is not finite";
  }
  for (int k = 0; k < s.w; ++k) {
    const GenericSensorSpec& sen = s.sensor[k];
    if (!generic_detail::finite(sen.offset) || !generic_detail::finite(sen.noise))
      return "a sensor value is not finite";
    if (sen.noise < 0.0f) return "a sensor's noise must be >= 0";
    if (!generic_detail::finite_all(s.C[k], s.m + s.n)) return "a sensor map value is not finite";
  }
  return nullptr;
}

// The plant's state and equations over a spec held by its owner: GenericPlant
// keeps its spec (configured at run time), FixedGenericPlant reads a
// constexpr one where it lies (in a HIL image's flash, not copied to RAM).
class GenericPlantState {
 public:
  void reseed_noise(uint32_t seed) { rng_.reseed(seed); }
  void reset(const GenericPlantSpec& spec, uint32_t seed) {
    rng_.reseed(seed);
    for (int i = 0; i < kGenericMaxM; ++i) {
      play_[i] = spec.input[i].neutral;
      a_[i] = 0.0f;
    }
    for (int j = 0; j < kGenericMaxN; ++j) {
      const GenericOutputSpec& o = spec.output[j];
      y_[j] = plant_detail::clampf(o.offset, o.lo, o.hi);
    }
  }

  void step(const GenericPlantSpec& spec, const float* u, float dt) {
    dt = plant_detail::admit_dt(dt);
    if (!(dt > 0.0f)) return;
    for (int i = 0; i < spec.m; ++i) {
      const GenericInputSpec& s = spec.input[i];
      const float ui = plant_detail::admit(u != nullptr ? u[i] : s.neutral, s.min, s.max, s.neutral);
      play_[i] = plant_detail::play(play_[i], ui, s.play);
      const float target = s.gain * generic_detail::shape(s, play_[i] - s.neutral);
      a_[i] = s.tau > 0.0f ? a_[i] + plant_detail::lag_gain(dt, s.tau) * (target - a_[i]) : target;
      if (!std::isfinite(a_[i])) a_[i] = 0.0f;
    }
    for (int j = 0; j < spec.n; ++j) {
      const GenericOutputSpec& o = spec.output[j];
      float target = o.offset;
      for (int i = 0; i < spec.m; ++i) target += spec.B[j][i] * a_[i];
      float y = o.tau > 0.0f ? y_[j] + plant_detail::lag_gain(dt, o.tau) * (target - y_[j]) : target;
      // A huge gain times a huge coupling can overflow float: the box holds.
      if (!std::isfinite(y)) y = target > 0.0f ? o.hi : o.lo;
      y_[j] = plant_detail::clampf(y, o.lo, o.hi);
    }
  }

  void output(const GenericPlantSpec& spec, float* y) const {
    for (int j = 0; j < spec.n; ++j) y[j] = y_[j];
  }

  void sensors(const GenericPlantSpec& spec, float* l) {
    const int m = spec.m;
    for (int k = 0; k < spec.w; ++k) {
      const float* row = spec.C[k];
      float v = spec.sensor[k].offset;
      for (int i = 0; i < m; ++i) v += row[i] * a_[i];
      for (int j = 0; j < spec.n; ++j) v += row[m + j] * y_[j];
      if (spec.sensor[k].noise > 0.0f) v += spec.sensor[k].noise * rng_.gaussian();
      l[k] = std::isfinite(v) ? v : spec.sensor[k].offset;
    }
  }

  static void input_limits(const GenericPlantSpec& spec, float* umin, float* umax) {
    for (int i = 0; i < spec.m; ++i) {
      umin[i] = spec.input[i].min;
      umax[i] = spec.input[i].max;
    }
  }
  static void neutral_input(const GenericPlantSpec& spec, float* u) {
    for (int i = 0; i < spec.m; ++i) u[i] = spec.input[i].neutral;
  }
  static void output_box(const GenericPlantSpec& spec, float* lo, float* hi) {
    for (int j = 0; j < spec.n; ++j) {
      lo[j] = spec.output[j].lo;
      hi[j] = spec.output[j].hi;
    }
  }

  float actuator(int i) const { return a_[i]; }

 private:
  float play_[kGenericMaxM] = {};
  float a_[kGenericMaxM] = {};
  float y_[kGenericMaxN] = {};
  Rng rng_{0};
};

class GenericPlant {
 public:
  GenericPlant() { reset(0); }
  explicit GenericPlant(const GenericPlantSpec& spec, uint32_t seed = 0) {
    configure(spec);
    reset(seed);
  }

  // Takes `spec` (copied) and resets to rest; refuses a spec
  // generic_spec_problem() finds fault with and keeps the previous one.
  bool configure(const GenericPlantSpec& spec, uint32_t seed = 0) {
    if (generic_spec_problem(spec) != nullptr) return false;
    spec_ = spec;
    reset(seed);
    return true;
  }
  const GenericPlantSpec& spec() const { return spec_; }

  int m() const { return spec_.m; }
  int n() const { return spec_.n; }
  int w() const { return spec_.w; }
  float dt() const { return spec_.dt; }

  void reset(uint32_t seed = 0) { state_.reset(spec_, seed); }
  void reseed_noise(uint32_t seed) { state_.reseed_noise(seed); }
  void step(const float* u, float dt) { state_.step(spec_, u, dt); }
  void output(float* y) const { state_.output(spec_, y); }
  void sensors(float* l) { state_.sensors(spec_, l); }

  void input_limits(float* umin, float* umax) const { GenericPlantState::input_limits(spec_, umin, umax); }
  void neutral_input(float* u) const { GenericPlantState::neutral_input(spec_, u); }
  void output_box(float* lo, float* hi) const { GenericPlantState::output_box(spec_, lo, hi); }

  // The steady output for input u held long enough after a step from rest
  // (the neutral input), where each play operator stops `play` short of u:
  // clamp(offset + B s(p)).
  void static_output(const float* u, float* y) const {
    float a[kGenericMaxM];
    for (int i = 0; i < spec_.m; ++i) {
      const GenericInputSpec& s = spec_.input[i];
      const float ui = plant_detail::admit(u[i], s.min, s.max, s.neutral);
      const float p = ui - s.play > s.neutral ? ui - s.play : (ui + s.play < s.neutral ? ui + s.play : s.neutral);
      a[i] = s.gain * generic_detail::shape(s, p - s.neutral);
    }
    for (int j = 0; j < spec_.n; ++j) {
      float t = spec_.output[j].offset;
      for (int i = 0; i < spec_.m; ++i) t += spec_.B[j][i] * a[i];
      y[j] = plant_detail::clampf(t, spec_.output[j].lo, spec_.output[j].hi);
    }
  }

  // Actuator state a_i (for tests and plots).
  float actuator(int i) const { return state_.actuator(i); }

 private:
  GenericPlantSpec spec_{};
  GenericPlantState state_;
};

// A generic plant of a spec fixed at compile time, with the named plants'
// shape (shared/plant.hpp: constant m, n, w, kDt, static limits): what a HIL
// image carries for a rig file's `[plant] kind = "generic"` (its generated
// nlsoft_rig.hpp holds the spec, app/firmware/image_header.cpp). The spec
// stays where it is (flash); only the state (about 100 bytes) is the
// plant's. Steps bit for bit as GenericPlant does with the same spec.
template <const GenericPlantSpec& Spec>
class FixedGenericPlant {
  static_assert(generic_spec_problem(Spec) == nullptr, "the plant spec is one generic_spec_problem() refuses");

 public:
  static constexpr int m = Spec.m, n = Spec.n, w = Spec.w;
  static constexpr float kDt = Spec.dt;

  void reset(uint32_t seed = 0) { state_.reset(Spec, seed); }
  void reseed_noise(uint32_t seed) { state_.reseed_noise(seed); }
  void step(const float* u, float dt) { state_.step(Spec, u, dt); }
  void output(float* y) const { state_.output(Spec, y); }
  void sensors(float* l) { state_.sensors(Spec, l); }

  static void input_limits(float* umin, float* umax) { GenericPlantState::input_limits(Spec, umin, umax); }
  static void neutral_input(float* u) { GenericPlantState::neutral_input(Spec, u); }
  static void output_box(float* lo, float* hi) { GenericPlantState::output_box(Spec, lo, hi); }

  float actuator(int i) const { return state_.actuator(i); }

 private:
  GenericPlantState state_;
};

}  // namespace nlsoft
