#pragma once
// Which of the simulated plants compiled into the console a rig names
// (`[plant] kind`): what `simulate` and `--sim` run for a rig without a
// generic plant (app/rig/rig_plant.hpp). The Cortex-M images and the
// simulator are built from, or serve, the rig file itself, so nothing goes
// by the shipped rigs' names any more.
#include <string>

#include "app/rig/rig.hpp"
#include "shared/platform_id.hpp"

namespace nlsoft::console {

// The simulated plant of `rig`; throws CliError when it has none.
PlatformId simulated_plant(const Rig& rig, const std::string& what);

}  // namespace nlsoft::console
