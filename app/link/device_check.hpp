#pragma once
// `rig check RIG PORT`'s live half: the rig file beside the firmware at PORT, which says
// how each of the file's sensor chips answers (DEVICE_GET, protocol 1.4).
#include <string>
#include <vector>

#include "protocol/messages.hpp"

#include "host/rig/rig.hpp"

namespace nlsoft::console {

// Prints the firmware's rig (name, whether its hash is this file's) and one
// line per sensor chip; returns 0 when every chip of the file is ok, 1 when
// one is not (absent, wrong id, stopped, or missing from the firmware).
// Throws LinkError/CliError when the firmware cannot be asked.
int check_live_devices(const host::Rig& rig, const std::string& port, unsigned baud);

// One line per chip, as the firmware reports it (DEVICE_GET) beside the rig
// file: "device mag1       lis3mdl on spi2 chip select PB12: absent, no
// sample yet, 3 faults", then the file's chips the firmware lacks. `bad`
// counts the chips not ok. What `rig check` and the script's `devices` print.
std::vector<std::string> device_lines(const host::Rig& rig, const std::vector<protocol::DeviceStatus>& found, int& bad);

}  // namespace nlsoft::console
