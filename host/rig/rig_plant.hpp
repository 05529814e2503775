#pragma once
// A rig's simulated stand-in (`[plant] kind`, docs/rig-file.md): one of the
// plant registry's rows (shared/plant_registry.hpp), the generic one with
// its spec from the file's [plant] table.
#include <string>

#include "host/rig/rig.hpp"
#include "shared/plant_generic.hpp"

namespace nlsoft::host {

// True for `[plant] kind = "generic"`.
bool has_generic_plant(const Rig& rig);

// The spec of a rig's generic plant: its limits and neutral inputs, the
// outputs' [min, max] as the box, 1 / rate_hz as the period, and the
// [plant] constants, in float. Only for has_generic_plant(rig).
GenericPlantSpec generic_plant_spec(const Rig& rig);

// The registry's row of the plant that simulates `rig`; throws CliError
// (`what` first) for a rig without a [plant].
const PlantEntry& simulated_plant(const Rig& rig, const std::string& what);

}  // namespace nlsoft::host
