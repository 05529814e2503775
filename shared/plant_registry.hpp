// The simulated plants the product carries, in one table: the hand-written
// plants and the generic one a rig file describes key by key. The simulator
// (SimPlant), the rig loader (`[plant] kind`) and the image generator read
// a plant's name, dimensions and period here and nowhere else; adding a
// hand-written plant is one row and one class.
#pragma once

#include <cstdint>
#include <cstring>
#include <tuple>

#include "shared/plant.hpp"
#include "shared/plant_generic.hpp"
#include "shared/plant_hasel.hpp"
#include "shared/plant_msd.hpp"
#include "shared/plant_tendon.hpp"

namespace nlsoft {

// A plant's row in kPlantRegistry (its index there).
enum class PlantKind : uint8_t { Msd = 0, Hasel = 1, Tendon = 2, Generic = 3 };

// One of each plant, where SimPlant keeps the one it runs.
using PlantSet = std::tuple<MsdPlant, HaselPlant, TendonPlant, GenericPlant>;

// What every plant offers (shared/plant.hpp), reached through the set.
struct PlantOps {
  int (*m)(const PlantSet&);
  int (*n)(const PlantSet&);
  int (*w)(const PlantSet&);
  float (*dt)(const PlantSet&);
  void (*reset)(PlantSet&, uint32_t seed);
  void (*reseed_noise)(PlantSet&, uint32_t seed);
  void (*step)(PlantSet&, const float* u, float dt);
  void (*output)(const PlantSet&, float* y);
  void (*sensors)(PlantSet&, float* l);
  void (*input_limits)(const PlantSet&, float* umin, float* umax);
  void (*neutral_input)(const PlantSet&, float* u);
  void (*output_box)(const PlantSet&, float* lo, float* hi);
};

namespace plant_detail {

// A hand-written plant's dimensions are constants; the generic plant's its spec's.
template <class P>
struct Shape {
  static int m(const P&) { return P::m; }
  static int n(const P&) { return P::n; }
  static int w(const P&) { return P::w; }
  static float dt(const P&) { return P::kDt; }
};
template <>
struct Shape<GenericPlant> {
  static int m(const GenericPlant& p) { return p.m(); }
  static int n(const GenericPlant& p) { return p.n(); }
  static int w(const GenericPlant& p) { return p.w(); }
  static float dt(const GenericPlant& p) { return p.dt(); }
};

template <class P>
constexpr PlantOps ops_of() {
  return {
      [](const PlantSet& s) { return Shape<P>::m(std::get<P>(s)); },
      [](const PlantSet& s) { return Shape<P>::n(std::get<P>(s)); },
      [](const PlantSet& s) { return Shape<P>::w(std::get<P>(s)); },
      [](const PlantSet& s) { return Shape<P>::dt(std::get<P>(s)); },
      [](PlantSet& s, uint32_t seed) { std::get<P>(s).reset(seed); },
      [](PlantSet& s, uint32_t seed) { std::get<P>(s).reseed_noise(seed); },
      [](PlantSet& s, const float* u, float dt) { std::get<P>(s).step(u, dt); },
      [](const PlantSet& s, float* y) { std::get<P>(s).output(y); },
      [](PlantSet& s, float* l) { std::get<P>(s).sensors(l); },
      [](const PlantSet& s, float* lo, float* hi) { std::get<P>(s).input_limits(lo, hi); },
      [](const PlantSet& s, float* u) { std::get<P>(s).neutral_input(u); },
      [](const PlantSet& s, float* lo, float* hi) { std::get<P>(s).output_box(lo, hi); },
  };
}

}  // namespace plant_detail

struct PlantEntry {
  PlantKind kind;
  const char* name;  // as a rig file's `[plant] kind` spells it
  // Fixed dimensions and period of a hand-written plant; 0 for the generic
  // plant, whose rig file gives them (its tables and 1 / rate_hz).
  uint8_t m, n, w;
  float period;  // s
  // Where an MCU image finds the plant: its header and class (the generic
  // plant's class is made from the rig's spec, so none).
  const char* header;
  const char* type;
  PlantOps ops;  // the factory: how SimPlant runs this plant
  // How `dataset` excites it; the generic plant's come from its spec.
  DatasetScales dataset;
};

template <class P>
constexpr PlantEntry hand_written(PlantKind kind, const char* name, const char* header, const char* type) {
  return {kind,   name, uint8_t(P::m), uint8_t(P::n), uint8_t(P::w), P::kDt, header, type, plant_detail::ops_of<P>(),
          P::kDataset};
}

inline constexpr PlantEntry kPlantRegistry[] = {
    hand_written<MsdPlant>(PlantKind::Msd, "msd", "shared/plant_msd.hpp", "MsdPlant"),
    hand_written<HaselPlant>(PlantKind::Hasel, "hasel", "shared/plant_hasel.hpp", "HaselPlant"),
    hand_written<TendonPlant>(PlantKind::Tendon, "tendon", "shared/plant_tendon.hpp", "TendonPlant"),
    {PlantKind::Generic, "generic", 0, 0, 0, 0.0f, "shared/plant_generic.hpp", nullptr,
     plant_detail::ops_of<GenericPlant>(), DatasetScales{}},
};
constexpr int kPlantCount = int(sizeof(kPlantRegistry) / sizeof(kPlantRegistry[0]));

constexpr bool registry_indexed_by_kind() {
  for (int i = 0; i < kPlantCount; ++i)
    if (int(kPlantRegistry[i].kind) != i) return false;
  return true;
}
static_assert(registry_indexed_by_kind(), "kPlantRegistry is indexed by PlantKind");
static_assert(std::tuple_size<PlantSet>::value == kPlantCount, "one PlantSet member per registered plant");
static_assert(MsdPlant::m <= kMaxPlantM && HaselPlant::m <= kMaxPlantM && TendonPlant::m <= kMaxPlantM,
              "kMaxPlantM too small");
static_assert(MsdPlant::n <= kMaxPlantN && HaselPlant::n <= kMaxPlantN && TendonPlant::n <= kMaxPlantN,
              "kMaxPlantN too small");
static_assert(MsdPlant::w <= kMaxPlantW && HaselPlant::w <= kMaxPlantW && TendonPlant::w <= kMaxPlantW,
              "kMaxPlantW too small");
static_assert(kGenericMaxM <= kMaxPlantM && kGenericMaxN <= kMaxPlantN && kGenericMaxW <= kMaxPlantW,
              "SimPlant's capacity must hold every generic plant");

// The registered plant so named; nullptr for any other name.
inline const PlantEntry* find_plant(const char* name) {
  if (name == nullptr) return nullptr;
  for (const PlantEntry& e : kPlantRegistry)
    if (std::strcmp(e.name, name) == 0) return &e;
  return nullptr;
}

// The registered plant of `kind`; nullptr for a value no row carries.
inline const PlantEntry* plant_entry(PlantKind kind) {
  return uint8_t(kind) < kPlantCount ? &kPlantRegistry[uint8_t(kind)] : nullptr;
}

}  // namespace nlsoft
