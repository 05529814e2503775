#include "app/model/excitation.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "app/model/error.hpp"
#include "app/model/random.hpp"
#include "shared/fixed_math.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::model {
namespace {

constexpr double kTwoPi = 6.283185307179586;

enum class Mode { Steps, Walk, Chirp, Paper };

using Scales = DatasetScales;

// A generic plant's scales from its slowest lag T (two periods when it has
// none), proportioned as hasel's are to its 25-45 ms: levels held from T to
// 35 T, chirps up to about its corner frequency and below Nyquist, every
// input drawn on its own over its whole range.
Scales scales_for(const GenericPlantSpec& g) {
  double T = 0.0;
  for (int i = 0; i < g.m; ++i) T = std::max(T, double(g.input[i].tau));
  for (int j = 0; j < g.n; ++j) T = std::max(T, double(g.output[j].tau));
  const double dt = double(g.dt);
  T = std::max(T, 2.0 * dt);
  const double hold_min = T, hold_max = std::max(4.0 * hold_min, 35.0 * T);
  const double seg_min = std::max(3.0, 2.0 * hold_max);
  const double f_max = std::min(0.25 / dt, 1.0 / (kTwoPi * T));
  return {hold_min, hold_max, seg_min, 5.0 * seg_min, f_max / 80.0, f_max, 4.0 * T, 0.5, false, 0.03, false};
}

// The rig's generic plant, selected and reset; throws for a spec it refuses.
void select_generic(SimPlant& plant, const PlantTarget& t, uint32_t seed) {
  if (!plant.select(t.generic, seed))
    throw PipelineError("rig '" + t.name + "': its generic plant cannot run: " + generic_spec_problem(t.generic));
}

// A hand-written plant, selected and reset; throws for the generic one.
void select_hand_written(SimPlant& plant, PlantKind kind, uint32_t seed) {
  if (!plant.select(kind, seed))
    throw PipelineError("plant kind " + std::to_string(int(kind)) +
                        " is no hand-written plant (the generic plant needs its rig's spec)");
}

class Excitation {
 public:
  Excitation(const Scales& scales, const SimPlant& plant, uint32_t seed)
      : paper_(scales.paper_input), s_(scales), rng_(seed ^ 0x9e3779b97f4a7c15ull), m_(plant.m()), dt_(plant.dt()) {
    float lo[kMaxPlantM], hi[kMaxPlantM];
    plant.input_limits(lo, hi);
    lo_.assign(lo, lo + m_);
    hi_.assign(hi, hi + m_);
    v_.assign(size_t(m_), 0.5);
    hold_.assign(size_t(m_), 0);
    walk_.assign(size_t(m_), 0.5);
    phase_.assign(size_t(m_), 0.0);
    amp_.assign(size_t(m_), 0.0);
    centre_.assign(size_t(m_), 0.5);
  }

  void next(float* u) {
    if (left_ <= 0) start_segment();
    --left_;
    t_seg_ += dt_;
    t_ += dt_;
    for (int i = 0; i < m_; ++i) {
      double v = 0.5;
      switch (mode_) {
        case Mode::Steps: v = step_value(i); break;
        case Mode::Walk: v = walk_value(i); break;
        case Mode::Chirp: v = chirp_value(i); break;
        case Mode::Paper: v = 0.5; break;
      }
      v += dither_ * (2.0 * rng_.uniform() - 1.0);
      v = std::clamp(v, 0.0, 1.0);
      double ui = lo_[size_t(i)] + v * (hi_[size_t(i)] - lo_[size_t(i)]);
      if (mode_ == Mode::Paper) ui = 1000.0 * fixed_math::sin(t_) * fixed_math::cos(t_);
      u[i] = static_cast<float>(ui);
    }
  }

 private:
  double common() { return s_.common_level ? rng_.uniform(0.05, 0.95) : 0.5; }
  double level() { return std::clamp(common_ + rng_.uniform(-spread_, spread_), 0.0, 1.0); }
  long seconds(double t) const { return std::max(1L, static_cast<long>(std::lround(t / dt_))); }

  void start_segment() {
    const double r = rng_.uniform();
    if (paper_)
      mode_ = r < 0.25 ? Mode::Paper : r < 0.6 ? Mode::Steps : r < 0.8 ? Mode::Chirp : Mode::Walk;
    else
      mode_ = r < 0.5 ? Mode::Steps : r < 0.8 ? Mode::Walk : Mode::Chirp;
    left_ = seconds(rng_.uniform(s_.seg_min, s_.seg_max));
    t_seg_ = 0.0;
    common_ = common();
    spread_ = s_.common_level ? rng_.uniform(0.15, s_.spread) : s_.spread;
    dither_ = mode_ == Mode::Paper ? 0.0 : rng_.uniform(0.0, s_.dither);
    f0_ = s_.f_min * rng_.uniform(1.0, 2.0);
    f1_ = s_.f_max * rng_.uniform(0.3, 1.0);
    seg_len_ = static_cast<double>(left_) * dt_;
    for (int i = 0; i < m_; ++i) {
      hold_[size_t(i)] = 0;
      walk_[size_t(i)] = v_[size_t(i)];
      phase_[size_t(i)] = rng_.uniform(0.0, kTwoPi);
      amp_[size_t(i)] = rng_.uniform(0.3, 1.0) * spread_;
      centre_[size_t(i)] = level();
    }
  }

  double step_value(int i) {
    if (hold_[size_t(i)]-- <= 0) {
      if (rng_.uniform() < 0.15) common_ = common();
      v_[size_t(i)] = level();
      hold_[size_t(i)] = seconds(rng_.uniform(s_.hold_min, s_.hold_max));
    }
    return v_[size_t(i)];
  }

  // Ornstein-Uhlenbeck around the common level, then a first-order smoother.
  double walk_value(int i) {
    const double sigma = spread_ * std::sqrt(2.0 * dt_ / s_.walk_tau) * 2.0;
    double& r = walk_[size_t(i)];
    r += (dt_ / (4.0 * s_.walk_tau)) * (common_ - r) + sigma * rng_.gaussian();
    if (r < 0.0) r = -r;
    if (r > 1.0) r = 2.0 - r;
    const double a = dt_ / (s_.walk_tau + dt_);
    v_[size_t(i)] += a * (r - v_[size_t(i)]);
    return v_[size_t(i)];
  }

  // Logarithmic sweep f0 -> f1 over the segment, per-actuator phase.
  double chirp_value(int i) {
    const double frac = std::min(1.0, t_seg_ / seg_len_);
    const double f = f0_ * fixed_math::pow(f1_ / f0_, frac);
    if (i == 0) chirp_phase_ += kTwoPi * f * dt_;
    v_[size_t(i)] = centre_[size_t(i)] + amp_[size_t(i)] * fixed_math::sin(chirp_phase_ * (1.0 + 0.13 * i) + phase_[size_t(i)]);
    return v_[size_t(i)];
  }

  bool paper_;
  Scales s_;
  Random rng_;
  int m_;
  double dt_;
  std::vector<double> lo_, hi_, v_, walk_, phase_, amp_, centre_;
  std::vector<long> hold_;
  Mode mode_ = Mode::Steps;
  long left_ = 0;
  double t_ = 0.0, t_seg_ = 0.0, seg_len_ = 1.0;
  double common_ = 0.5, spread_ = 0.5, dither_ = 0.0, f0_ = 0.1, f1_ = 1.0, chirp_phase_ = 0.0;
};

}  // namespace

long default_steps(const PlantTarget&) { return 120000; }

namespace {

// Row k holds u(k), y(k), l(k) of `plant` (selected and reset) driven by `ex`.
Series record(SimPlant& plant, Excitation& ex, long steps) {
  const int m = plant.m(), n = plant.n(), w = plant.w();
  Series s;
  s.resize(steps, m, n, w);
  float u[kMaxPlantM] = {}, y[kMaxPlantN] = {}, l[kMaxPlantW] = {};
  const double dt = plant.dt();
  for (long k = 0; k < steps; ++k) {
    plant.output(y);
    plant.sensors(l);
    ex.next(u);
    s.time(k) = static_cast<double>(k) * dt;
    for (int i = 0; i < m; ++i) s.u(k, i) = u[i];
    for (int j = 0; j < n; ++j) s.y(k, j) = y[j];
    for (int i = 0; i < w; ++i) s.l(k, i) = l[i];
    plant.step(u, plant.dt());
  }
  return s;
}

void settle_at_neutral(SimPlant& plant, double* y) {
  float u[kMaxPlantM] = {}, out[kMaxPlantN] = {};
  plant.neutral_input(u);
  const int settle = static_cast<int>(3.0f / plant.dt());
  for (int k = 0; k < settle; ++k) plant.step(u, plant.dt());
  plant.output(out);
  for (int j = 0; j < plant.n(); ++j) y[j] = out[j];
}

}  // namespace

Series generate_excitation(PlantKind kind, long steps, uint32_t seed) {
  if (steps < 100) throw PipelineError("--steps must be at least 100");
  SimPlant plant;
  select_hand_written(plant, kind, seed);
  Excitation ex(plant_entry(kind)->dataset, plant, seed);
  return record(plant, ex, steps);
}

Series generate_excitation(const PlantTarget& t, long steps, uint32_t seed) {
  if (t.plant == TargetPlant::Named) return generate_excitation(t.kind, steps, seed);
  if (t.plant == TargetPlant::None)
    throw PipelineError("rig '" + t.name + "' has no [plant]: nothing simulates it, so there is no data to record "
                        "(record the rig itself, or give the rig file a [plant])");
  if (steps < 100) throw PipelineError("--steps must be at least 100");
  SimPlant plant;
  select_generic(plant, t, seed);
  Excitation ex(scales_for(t.generic), plant, seed);
  return record(plant, ex, steps);
}

void neutral_output(PlantKind kind, double* y) {
  SimPlant plant;
  select_hand_written(plant, kind, 0);
  settle_at_neutral(plant, y);
}

void neutral_output(const PlantTarget& t, double* y) {
  if (t.plant == TargetPlant::Named) return neutral_output(t.kind, y);
  if (t.plant == TargetPlant::None) {
    for (int j = 0; j < t.n; ++j) y[j] = t.y_rest[size_t(j)];
    return;
  }
  SimPlant plant;
  select_generic(plant, t, 0);
  settle_at_neutral(plant, y);
}

}  // namespace nlsoft::model
