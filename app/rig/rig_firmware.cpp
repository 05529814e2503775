#include "app/rig/rig_firmware.hpp"

#include <fmt/format.h>

#include "app/cli_error.hpp"

namespace nlsoft::console {

namespace {

std::string compiled_names() {
  std::string s;
  for (int i = 0; i < kPlatformCount; ++i) s += std::string(s.empty() ? "" : ", ") + platform_name(PlatformId(i));
  return s;
}

}  // namespace

PlatformId simulated_plant(const Rig& rig, const std::string& what) {
  PlatformId id;
  if (rig.plant.kind.empty() || !platform_from_name(rig.plant.kind.c_str(), &id))
    throw CliError(fmt::format("{}: rig '{}' ({}) has no [plant]: nothing simulates it (the simulated plants are {}, "
                               "or kind = \"generic\" with the plant's constants: docs/rig-file.md)",
                               what, rig.name, rig.file, compiled_names()));
  return id;
}

}  // namespace nlsoft::console
