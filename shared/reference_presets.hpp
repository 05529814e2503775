#pragma once
// References sized for each platform's task space (docs/platforms.md,
// "References"), so the console, the firmware's start-up reference and the
// tests agree on what "Swirl on hasel" means. Centres and amplitudes come
// from the simulated plants' documented reachable sets.
#include "shared/plant_hasel.hpp"
#include "shared/plant_tendon.hpp"
#include "shared/platform.hpp"
#include "shared/reference.hpp"
#include "shared/rig_config.hpp"

namespace nlsoft {

// The paper's task of each rig: msd steps, hasel Swirl, tendon Infinity.
constexpr RefKind default_reference_kind(PlatformId id) {
  return id == PlatformId::Msd ? RefKind::Step : (id == PlatformId::Hasel ? RefKind::Swirl : RefKind::Infinity);
}

// Periodic paths take kPeriodS per lap at the platform's loop rate.
constexpr RefParams reference_preset(PlatformId platform, RefKind kind) {
  constexpr float kPi = 3.14159265358979f;
  constexpr float kPeriodS = 8.0f;
  const float rate = preset(platform).rate_hz;
  RefParams r{};
  r.kind = kind;
  r.hold = 1;
  r.scale = 1.0f;
  r.omega = 2.0f * kPi / (kPeriodS * rate);
  r.lambda = kPeriodS * rate;
  switch (platform) {
    case PlatformId::Msd:
      r.A = r.B = r.C = 0.5f;
      break;
    case PlatformId::Hasel:
      r.c[2] = 8.0f;
      r.A = r.B = r.C = 4.0f;
      break;
    case PlatformId::Tendon:
      for (int i = 0; i < 3; ++i) r.c[i] = TendonPlant::kCentre[i];
      r.A = TendonPlant::kInfinity[0], r.B = TendonPlant::kInfinity[1], r.C = TendonPlant::kInfinity[2];
      break;
    default:
      break;
  }
  switch (kind) {
    case RefKind::Pringle:
    case RefKind::Diagonal:
      if (platform == PlatformId::Tendon)
        r.A = TendonPlant::kPringle[0], r.B = TendonPlant::kPringle[1], r.C = TendonPlant::kPringle[2];
      break;
    case RefKind::Swirl:
      r.hold = 10;
      if (platform == PlatformId::Hasel) {
        for (int i = 0; i < 3; ++i) r.c[i] = HaselPlant::kSwirlCentre[i];
        r.scale = HaselPlant::kSwirlScale;
      }
      break;
    case RefKind::Step: {
      // the paper's msd task: 0.5 m, 1 m, 2 m, 10 s each
      const bool msd = platform == PlatformId::Msd;
      r.level_count = 3;
      r.levels[0] = msd ? 0.5f : 1.0f;
      r.levels[1] = msd ? 1.0f : 2.0f;
      r.levels[2] = msd ? 2.0f : 3.0f;
      const float hold = 10.0f * rate;
      r.hold = uint16_t(hold > 65535.0f ? 65535.0f : hold);
      break;
    }
    default:
      break;
  }
  return r;
}

// A shipped rig's compiled-in preset as the firmware's rig data, with the
// paper's task as its start-up reference (what rigs/<name>.toml says too:
// tests/app/rig compares them value for value).
constexpr RigConfig shipped_rig(PlatformId id) {
  const Preset& p = preset(id);
  RigConfig c{};
  c.name = platform_name(id);
  c.hash = 0;
  c.platform = id;
  c.m = p.m, c.n = p.n, c.w = p.w, c.nd = p.nd, c.dd = p.dd;
  c.rate_hz = p.rate_hz;
  for (int i = 0; i < p.m; ++i) {
    c.u_min[i] = p.u_min;
    c.u_max[i] = p.u_max;
    c.u_neutral[i] = 0.5f * (p.u_min + p.u_max);
    c.Lambda[i] = p.Lambda[i];
  }
  for (int i = 0; i < p.n; ++i) c.Q[i] = p.Q[i];
  c.s = p.s, c.b = p.b, c.r = p.r, c.eps = p.eps, c.nr_tol = 1e-4f;
  c.N = p.N, c.N1 = 1, c.Nc = p.Nc, c.nr_max_iter = p.nr_max_iter;
  c.mode = DerivMode::Exact;
  c.feedback = p.feedback;
  c.reference = reference_preset(id, default_reference_kind(id));
  return c;
}

}  // namespace nlsoft
