#include "host/rig/rig_reference.hpp"

namespace nlsoft::host {

RefParams rig_reference(const Rig& rig, RefKind kind) {
  // In float, as the MCU computes from these parameters: the console's
  // prediction of a path is the firmware's, bit for bit.
  constexpr float kPi = 3.14159265358979f;
  constexpr float kPeriodS = 8.0f;
  const float rate = float(rig.rate_hz);
  const RigReference& g = rig.reference;
  RefParams r{};
  r.kind = kind;
  r.hold = 1;
  r.scale = 1.0f;
  r.omega = 2.0f * kPi / (kPeriodS * rate);
  r.lambda = kPeriodS * rate;
  for (int i = 0; i < 3; ++i) r.c[i] = float(g.centre[size_t(i)]);
  r.A = float(g.amplitude[0]), r.B = float(g.amplitude[1]), r.C = float(g.amplitude[2]);
  switch (kind) {
    case RefKind::Pringle:
    case RefKind::Diagonal:
      r.A = float(g.pringle_amplitude[0]), r.B = float(g.pringle_amplitude[1]), r.C = float(g.pringle_amplitude[2]);
      break;
    case RefKind::Swirl:
      r.hold = 10;
      for (int i = 0; i < 3; ++i) r.c[i] = float(g.swirl_centre[size_t(i)]);
      r.scale = float(g.swirl_scale);
      break;
    case RefKind::Step: {
      r.level_count = uint8_t(g.step_levels.size());
      for (size_t i = 0; i < g.step_levels.size() && i < size_t(kRefMaxLevels); ++i) r.levels[i] = float(g.step_levels[i]);
      const float hold = 10.0f * rate;
      r.hold = uint16_t(hold > 65535.0f ? 65535.0f : hold);
      break;
    }
    default:
      break;
  }
  return r;
}

const char* reference_kind_name(RefKind k) {
  switch (k) {
    case RefKind::Infinity: return "infinity";
    case RefKind::Pringle: return "pringle";
    case RefKind::Diagonal: return "diagonal";
    case RefKind::Swirl: return "swirl";
    case RefKind::Step: return "steps";
    case RefKind::Table: return "table";
    case RefKind::Hold: return "hold";
  }
  return "?";
}

}  // namespace nlsoft::host
