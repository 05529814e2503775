#pragma once
// `rig check RIG PORT`'s live half: the rig file beside the firmware at PORT, which says
// how each of the file's sensor chips answers (DEVICE_GET, protocol 1.4).
#include <string>

#include "host/rig/rig.hpp"

namespace nlsoft::console {

// Prints the firmware's rig (name, whether its hash is this file's) and one
// line per sensor chip; returns 0 when every chip of the file is ok, 1 when
// one is not (absent, wrong id, stopped, or missing from the firmware).
// Throws LinkError/CliError when the firmware cannot be asked.
int check_live_devices(const Rig& rig, const std::string& port, unsigned baud);

}  // namespace nlsoft::console
