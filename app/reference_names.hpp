#pragma once
// Reference paths sized for each platform's task space, by name.
#include <string>
#include <vector>

#include "app/rig/rig.hpp"
#include "shared/platform_id.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

// Names accepted by --reference: infinity, pringle, diagonal, swirl, steps, hold.
const std::vector<std::string>& reference_names();

// Throws CliError for an unknown name.
RefParams reference_preset(PlatformId platform, const std::string& name);

// The platform's default task (paper): msd steps, hasel swirl, tendon infinity.
std::string default_reference(PlatformId platform);

// The same for a rig file: its [reference] geometry and default kind.
RefParams reference_preset(const Rig& rig, const std::string& name);
std::string default_reference(const Rig& rig);

}  // namespace nlsoft::console
