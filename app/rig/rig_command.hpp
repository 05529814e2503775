#pragma once
// `nlsoft-console rig check NAME|PATH` and `rig list`.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "host/rig/rig.hpp"

namespace nlsoft::console {

// `rig check RIG PORT`: the rig's sensor chips as the firmware at PORT sees
// them (app/link/device_check.hpp); returns the exit code.
using LiveDeviceCheck = std::function<int(const host::Rig& rig, const std::string& port, unsigned baud)>;

void add_rig_command(CLI::App& app, LiveDeviceCheck check_live);

}  // namespace nlsoft::console
