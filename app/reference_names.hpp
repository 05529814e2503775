#pragma once
// Reference paths sized for a rig's task space (its [reference]), by name.
#include <string>
#include <vector>

#include "host/rig/rig.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

// Names accepted by --reference: infinity, pringle, diagonal, swirl, steps, hold.
const std::vector<std::string>& reference_names();

// The path `name` on `rig` (its [reference] geometry); throws CliError for
// an unknown name.
RefParams reference_by_name(const host::Rig& rig, const std::string& name);
// The rig's default task: its [reference] kind.
std::string default_reference(const host::Rig& rig);

}  // namespace nlsoft::console
