// One simulated plant chosen at run time, by PlatformId (the three
// hand-written plants) or by a GenericPlantSpec (any rig described as data),
// for the host simulation and the posix firmware port. A tagged holder
// instead of virtual functions: it keeps one of each (the hand-written ones
// < 200 bytes together, the generic one its ~2.5 kB spec) and forwards to
// the selected one; no heap, no vtable.
// Dimensions never exceed kMaxPlantM, kMaxPlantN, kMaxPlantW (shared/plant.hpp).
#pragma once

#include <cstdint>

#include "shared/plant.hpp"
#include "shared/plant_generic.hpp"
#include "shared/plant_hasel.hpp"
#include "shared/plant_msd.hpp"
#include "shared/plant_tendon.hpp"
#include "shared/platform_id.hpp"

namespace nlsoft {

static_assert(MsdPlant::m <= kMaxPlantM && HaselPlant::m <= kMaxPlantM &&
                  TendonPlant::m <= kMaxPlantM,
              "kMaxPlantM too small");
static_assert(MsdPlant::n <= kMaxPlantN && HaselPlant::n <= kMaxPlantN &&
                  TendonPlant::n <= kMaxPlantN,
              "kMaxPlantN too small");
static_assert(MsdPlant::w <= kMaxPlantW && HaselPlant::w <= kMaxPlantW &&
                  TendonPlant::w <= kMaxPlantW,
              "kMaxPlantW too small");
static_assert(kGenericMaxM <= kMaxPlantM && kGenericMaxN <= kMaxPlantN && kGenericMaxW <= kMaxPlantW,
              "SimPlant's capacity must hold every generic plant");

class SimPlant {
 public:
  explicit SimPlant(PlatformId id = PlatformId::Msd, uint32_t seed = 0) { select(id, seed); }

  // Switches platform and resets it; an unknown id selects msd.
  void select(PlatformId id, uint32_t seed = 0) {
    id_ = (id == PlatformId::Hasel || id == PlatformId::Tendon) ? id : PlatformId::Msd;
    generic_selected_ = false;
    reset(seed);
  }

  // Switches to the generic plant `spec` describes and resets it; false (and
  // nothing changed) when generic_spec_problem() refuses the spec.
  bool select(const GenericPlantSpec& spec, uint32_t seed = 0) {
    if (!generic_.configure(spec, seed)) return false;
    generic_selected_ = true;
    return true;
  }

  // The hand-written plant selected; meaningless while is_generic().
  PlatformId id() const { return id_; }
  bool is_generic() const { return generic_selected_; }

  int m() const { return generic_selected_ ? generic_.m() : dispatch_dim(MsdPlant::m, HaselPlant::m, TendonPlant::m); }
  int n() const { return generic_selected_ ? generic_.n() : dispatch_dim(MsdPlant::n, HaselPlant::n, TendonPlant::n); }
  int w() const { return generic_selected_ ? generic_.w() : dispatch_dim(MsdPlant::w, HaselPlant::w, TendonPlant::w); }

  // The platform's own control period, s.
  float dt() const {
    if (generic_selected_) return generic_.dt();
    switch (id_) {
      case PlatformId::Hasel: return HaselPlant::kDt;
      case PlatformId::Tendon: return TendonPlant::kDt;
      default: return MsdPlant::kDt;
    }
  }

  void reset(uint32_t seed) {
    if (generic_selected_) return generic_.reset(seed);
    switch (id_) {
      case PlatformId::Hasel: hasel_.reset(seed); break;
      case PlatformId::Tendon: tendon_.reset(seed); break;
      default: msd_.reset(seed); break;
    }
  }

  // The noise starts over from `seed`, the state untouched (msd has none).
  void reseed_noise(uint32_t seed) {
    hasel_.reseed_noise(seed);
    tendon_.reseed_noise(seed);
    generic_.reseed_noise(seed);
  }

  void step(const float* u, float dt) {
    if (generic_selected_) return generic_.step(u, dt);
    switch (id_) {
      case PlatformId::Hasel: hasel_.step(u, dt); break;
      case PlatformId::Tendon: tendon_.step(u, dt); break;
      default: msd_.step(u, dt); break;
    }
  }

  void output(float* y) const {
    if (generic_selected_) return generic_.output(y);
    switch (id_) {
      case PlatformId::Hasel: hasel_.output(y); break;
      case PlatformId::Tendon: tendon_.output(y); break;
      default: msd_.output(y); break;
    }
  }

  void sensors(float* l) {
    if (generic_selected_) return generic_.sensors(l);
    switch (id_) {
      case PlatformId::Hasel: hasel_.sensors(l); break;
      case PlatformId::Tendon: tendon_.sensors(l); break;
      default: msd_.sensors(l); break;
    }
  }

  void input_limits(float* umin, float* umax) const {
    if (generic_selected_) return generic_.input_limits(umin, umax);
    switch (id_) {
      case PlatformId::Hasel: HaselPlant::input_limits(umin, umax); break;
      case PlatformId::Tendon: TendonPlant::input_limits(umin, umax); break;
      default: MsdPlant::input_limits(umin, umax); break;
    }
  }

  void neutral_input(float* u) const {
    if (generic_selected_) return generic_.neutral_input(u);
    switch (id_) {
      case PlatformId::Hasel: HaselPlant::neutral_input(u); break;
      case PlatformId::Tendon: TendonPlant::neutral_input(u); break;
      default: MsdPlant::neutral_input(u); break;
    }
  }

  void output_box(float* lo, float* hi) const {
    if (generic_selected_) return generic_.output_box(lo, hi);
    switch (id_) {
      case PlatformId::Hasel: HaselPlant::output_box(lo, hi); break;
      case PlatformId::Tendon: TendonPlant::output_box(lo, hi); break;
      default: MsdPlant::output_box(lo, hi); break;
    }
  }

  // Direct access for platform-specific set-up (msd initial state, ...).
  MsdPlant& msd() { return msd_; }
  HaselPlant& hasel() { return hasel_; }
  TendonPlant& tendon() { return tendon_; }
  GenericPlant& generic() { return generic_; }
  const GenericPlant& generic() const { return generic_; }

 private:
  int dispatch_dim(int msd, int hasel, int tendon) const {
    switch (id_) {
      case PlatformId::Hasel: return hasel;
      case PlatformId::Tendon: return tendon;
      default: return msd;
    }
  }

  PlatformId id_ = PlatformId::Msd;
  MsdPlant msd_;
  HaselPlant hasel_;
  TendonPlant tendon_;
  GenericPlant generic_;
  bool generic_selected_ = false;
};

}  // namespace nlsoft
