// Which rig a configuration, a simulated plant or a preset belongs to
// (docs/platforms.md). Kept apart so the protocol, the presets and the
// plants can all name a platform without including each other.
#pragma once

#include <cstdint>
#include <cstring>

namespace nlsoft {

// The numeric values travel on the wire: append, never renumber.
// Custom: a rig known only by its rig file (its name and hash travel apart).
enum class PlatformId : uint8_t { Msd = 0, Hasel = 1, Tendon = 2, Custom = 0xFF };

constexpr int kPlatformCount = 3;

// Lower-case names as the console spells them (`--platform msd`).
constexpr const char* platform_name(PlatformId id) {
  switch (id) {
    case PlatformId::Msd: return "msd";
    case PlatformId::Hasel: return "hasel";
    case PlatformId::Tendon: return "tendon";
    case PlatformId::Custom: return "custom";
  }
  return "?";
}

// Parses a name written by platform_name(); leaves *out untouched and returns
// false for anything else, so a bad command line changes nothing.
inline bool platform_from_name(const char* name, PlatformId* out) {
  if (name == nullptr || out == nullptr) return false;
  for (int i = 0; i < kPlatformCount; ++i) {
    const PlatformId id = static_cast<PlatformId>(i);
    if (std::strcmp(platform_name(id), name) == 0) {
      *out = id;
      return true;
    }
  }
  return false;
}

}  // namespace nlsoft
