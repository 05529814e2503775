#pragma once
// Which firmware runs a rig. The simulator and the Cortex-M images carry
// the shipped rigs compiled in (shared/platform.hpp), by name; until images
// are built from rig files, a rig has firmware only when it is one of those,
// value for value. Anything else is refused with what is missing, never run
// as some other rig.
#include <string>

#include "app/rig/rig.hpp"
#include "shared/platform_id.hpp"

namespace nlsoft::console {

// The compiled-in platform that is `rig`; throws CliError naming the file and
// what differs or is missing. `what` starts the message ("--sim").
PlatformId firmware_platform(const Rig& rig, const std::string& what);

// load_rig_arg then firmware_platform: the name the simulator and the image
// files use ("hasel").
std::string firmware_platform_name(const std::string& arg, const std::string& what);

// The simulated plant of `rig`; throws CliError when it has none.
PlatformId simulated_plant(const Rig& rig, const std::string& what);

}  // namespace nlsoft::console
