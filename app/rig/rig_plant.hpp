#pragma once
// A rig's generic simulated stand-in: the plant's spec from a
// `[plant] kind = "generic"` table (docs/rig-file.md).
#include "app/rig/rig.hpp"
#include "shared/plant_generic.hpp"

namespace nlsoft::console {

// True for `[plant] kind = "generic"`.
bool has_generic_plant(const Rig& rig);

// The spec of a rig's generic plant: its limits and neutral inputs, the
// outputs' [min, max] as the box, 1 / rate_hz as the period, and the
// [plant] constants, in float. Only for has_generic_plant(rig).
GenericPlantSpec generic_plant_spec(const Rig& rig);

// Refuses (CliError, `what` first) a rig with no plant to simulate: neither
// a generic one nor one of the named kinds.
void require_simulated_plant(const Rig& rig, const std::string& what);

}  // namespace nlsoft::console
