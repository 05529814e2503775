// One simulated plant chosen at run time from the plant registry
// (shared/plant_registry.hpp): a hand-written plant by its kind, or the
// generic plant by a GenericPlantSpec (any rig described as data), for the
// host simulation and the posix firmware port. It keeps one of each plant
// (the hand-written ones < 200 bytes together, the generic one its ~2.5 kB
// spec) and runs the selected one through its registry row; no heap.
// Dimensions never exceed kMaxPlantM, kMaxPlantN, kMaxPlantW (shared/plant.hpp).
#pragma once

#include <cstdint>

#include "shared/plant_registry.hpp"

namespace nlsoft {

class SimPlant {
 public:
  // The msd plant until select() picks another.
  SimPlant() { reset(0); }

  // Switches to the hand-written plant `kind` and resets it; false (and
  // nothing changed) for the generic plant, which needs its spec, and for a
  // value the registry has no row for.
  bool select(PlantKind kind, uint32_t seed = 0) {
    const PlantEntry* e = plant_entry(kind);
    if (e == nullptr || kind == PlantKind::Generic) return false;
    entry_ = e;
    reset(seed);
    return true;
  }

  // Switches to the generic plant `spec` describes and resets it; false (and
  // nothing changed) when generic_spec_problem() refuses the spec.
  bool select(const GenericPlantSpec& spec, uint32_t seed = 0) {
    if (!generic().configure(spec, seed)) return false;
    entry_ = plant_entry(PlantKind::Generic);
    return true;
  }

  const PlantEntry& entry() const { return *entry_; }
  PlantKind kind() const { return entry_->kind; }
  bool is_generic() const { return entry_->kind == PlantKind::Generic; }

  int m() const { return entry_->ops.m(plants_); }
  int n() const { return entry_->ops.n(plants_); }
  int w() const { return entry_->ops.w(plants_); }
  // The plant's own control period, s.
  float dt() const { return entry_->ops.dt(plants_); }

  void reset(uint32_t seed) { entry_->ops.reset(plants_, seed); }
  // The noise starts over from `seed`, the state untouched.
  void reseed_noise(uint32_t seed) { entry_->ops.reseed_noise(plants_, seed); }
  void step(const float* u, float dt) { entry_->ops.step(plants_, u, dt); }
  void output(float* y) const { entry_->ops.output(plants_, y); }
  void sensors(float* l) { entry_->ops.sensors(plants_, l); }
  void input_limits(float* umin, float* umax) const { entry_->ops.input_limits(plants_, umin, umax); }
  void neutral_input(float* u) const { entry_->ops.neutral_input(plants_, u); }
  void output_box(float* lo, float* hi) const { entry_->ops.output_box(plants_, lo, hi); }

  GenericPlant& generic() { return std::get<GenericPlant>(plants_); }
  const GenericPlant& generic() const { return std::get<GenericPlant>(plants_); }

 private:
  const PlantEntry* entry_ = &kPlantRegistry[uint8_t(PlantKind::Msd)];
  PlantSet plants_;
};

}  // namespace nlsoft
