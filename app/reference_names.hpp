#pragma once
// Reference paths sized for each platform's task space, by name.
#include <string>
#include <vector>

#include "shared/platform_id.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

// Names accepted by --reference: infinity, pringle, diagonal, swirl, steps, hold.
const std::vector<std::string>& reference_names();

// Throws CliError for an unknown name.
RefParams reference_preset(PlatformId platform, const std::string& name);

// The platform's default task (paper): msd steps, hasel swirl, tendon infinity.
std::string default_reference(PlatformId platform);

}  // namespace nlsoft::console
