#include "app/reference_presets.hpp"

#include <fmt/format.h>

#include <cmath>

#include "app/cli_error.hpp"
#include "shared/plant_hasel.hpp"
#include "shared/plant_tendon.hpp"
#include "shared/platform.hpp"

namespace nlsoft::console {

namespace {
constexpr float kPi = 3.14159265358979f;
constexpr float kPeriodS = 8.0f;  // one lap of a periodic path
}  // namespace

const std::vector<std::string>& reference_names() {
  static const std::vector<std::string> names = {"infinity", "pringle", "diagonal", "swirl", "steps", "hold"};
  return names;
}

std::string default_reference(PlatformId platform) {
  switch (platform) {
    case PlatformId::Msd: return "steps";
    case PlatformId::Hasel: return "swirl";
    case PlatformId::Tendon: return "infinity";
  }
  return "hold";
}

RefParams reference_preset(PlatformId platform, const std::string& name) {
  const float rate = preset(platform).rate_hz;
  RefParams r{};
  r.hold = 1;
  r.scale = 1.0f;
  r.omega = 2.0f * kPi / (kPeriodS * rate);
  r.lambda = kPeriodS * rate;
  // centre and amplitudes from the plants' documented reachable sets
  switch (platform) {
    case PlatformId::Msd:
      r.A = r.B = r.C = 0.5f;
      break;
    case PlatformId::Hasel:
      for (int i = 0; i < 3; ++i) r.c[i] = HaselPlant::kSwirlCentre[i];
      r.c[2] = 8.0f;
      r.A = 4.0f, r.B = 4.0f, r.C = 4.0f;
      break;
    case PlatformId::Tendon:
      for (int i = 0; i < 3; ++i) r.c[i] = TendonPlant::kCentre[i];
      r.A = TendonPlant::kInfinity[0], r.B = TendonPlant::kInfinity[1], r.C = TendonPlant::kInfinity[2];
      break;
  }
  if (name == "infinity") {
    r.kind = RefKind::Infinity;
  } else if (name == "pringle" || name == "diagonal") {
    r.kind = name == "pringle" ? RefKind::Pringle : RefKind::Diagonal;
    if (platform == PlatformId::Tendon)
      r.A = TendonPlant::kPringle[0], r.B = TendonPlant::kPringle[1], r.C = TendonPlant::kPringle[2];
  } else if (name == "swirl") {
    r.kind = RefKind::Swirl;
    r.hold = 10;
    if (platform == PlatformId::Hasel)
      for (int i = 0; i < 3; ++i) r.c[i] = HaselPlant::kSwirlCentre[i], r.scale = HaselPlant::kSwirlScale;
  } else if (name == "steps") {
    // the paper's msd task: 0.5 m, 1 m, 2 m
    r.kind = RefKind::Step;
    r.level_count = 3;
    r.levels[0] = 0.5f, r.levels[1] = 1.0f, r.levels[2] = 2.0f;
    r.hold = uint16_t(std::lround(10.0f * rate > 65535.0f ? 65535.0f : 10.0f * rate));
    if (platform != PlatformId::Msd) {
      r.levels[0] = 1.0f, r.levels[1] = 2.0f, r.levels[2] = 3.0f;
    }
  } else if (name == "hold") {
    r.kind = RefKind::Hold;
  } else {
    std::string known;
    for (const auto& n : reference_names()) known += (known.empty() ? "" : ", ") + n;
    throw CliError(fmt::format("unknown reference '{}'; known: {}", name, known));
  }
  return r;
}

}  // namespace nlsoft::console
