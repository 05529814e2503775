#pragma once
// A rig file as the firmware holds it (shared/rig_config.hpp): what the
// simulator serves and what a generated image header spells out.
#include "host/rig/rig.hpp"
#include "shared/rig_config.hpp"

namespace nlsoft::host {

// The rig's values in the firmware's form; `rig` must outlive the result
// (its name is pointed to, not copied). The start-up reference is the
// rig's [reference] task.
RigConfig firmware_rig(const Rig& rig);

}  // namespace nlsoft::host
