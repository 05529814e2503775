#pragma once
// Which compiled-in platform a rig is, for what still goes by the shipped
// rigs' names (`conformance --sim`): a rig is one of those only value for
// value, and anything else is refused with what differs, never run as some
// other rig. The Cortex-M images are built from the rig file itself
// (app/firmware/image_build.hpp), so --qemu and flash need no such check.
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
