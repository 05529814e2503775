// One simulated plant chosen at run time by PlatformId, for the host
// simulation and the posix firmware port. A tagged holder instead of virtual
// functions: all three plants are small (< 200 bytes together), so it keeps
// one of each and forwards to the selected one; no heap, no vtable.
// Dimensions never exceed kMaxPlantM, kMaxPlantN, kMaxPlantW (shared/plant.hpp).
#pragma once

#include <cstdint>

#include "shared/plant.hpp"
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

class SimPlant {
 public:
  explicit SimPlant(PlatformId id = PlatformId::Msd, uint32_t seed = 0) { select(id, seed); }

  // Switches platform and resets it; an unknown id selects msd.
  void select(PlatformId id, uint32_t seed = 0) {
    id_ = (id == PlatformId::Hasel || id == PlatformId::Tendon) ? id : PlatformId::Msd;
    reset(seed);
  }

  PlatformId id() const { return id_; }

  int m() const { return dispatch_dim(MsdPlant::m, HaselPlant::m, TendonPlant::m); }
  int n() const { return dispatch_dim(MsdPlant::n, HaselPlant::n, TendonPlant::n); }
  int w() const { return dispatch_dim(MsdPlant::w, HaselPlant::w, TendonPlant::w); }

  // The platform's own control period, s.
  float dt() const {
    switch (id_) {
      case PlatformId::Hasel: return HaselPlant::kDt;
      case PlatformId::Tendon: return TendonPlant::kDt;
      default: return MsdPlant::kDt;
    }
  }

  void reset(uint32_t seed) {
    switch (id_) {
      case PlatformId::Hasel: hasel_.reset(seed); break;
      case PlatformId::Tendon: tendon_.reset(seed); break;
      default: msd_.reset(seed); break;
    }
  }

  void step(const float* u, float dt) {
    switch (id_) {
      case PlatformId::Hasel: hasel_.step(u, dt); break;
      case PlatformId::Tendon: tendon_.step(u, dt); break;
      default: msd_.step(u, dt); break;
    }
  }

  void output(float* y) const {
    switch (id_) {
      case PlatformId::Hasel: hasel_.output(y); break;
      case PlatformId::Tendon: tendon_.output(y); break;
      default: msd_.output(y); break;
    }
  }

  void sensors(float* l) {
    switch (id_) {
      case PlatformId::Hasel: hasel_.sensors(l); break;
      case PlatformId::Tendon: tendon_.sensors(l); break;
      default: msd_.sensors(l); break;
    }
  }

  void input_limits(float* umin, float* umax) const {
    switch (id_) {
      case PlatformId::Hasel: HaselPlant::input_limits(umin, umax); break;
      case PlatformId::Tendon: TendonPlant::input_limits(umin, umax); break;
      default: MsdPlant::input_limits(umin, umax); break;
    }
  }

  void neutral_input(float* u) const {
    switch (id_) {
      case PlatformId::Hasel: HaselPlant::neutral_input(u); break;
      case PlatformId::Tendon: TendonPlant::neutral_input(u); break;
      default: MsdPlant::neutral_input(u); break;
    }
  }

  void output_box(float* lo, float* hi) const {
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
};

}  // namespace nlsoft
