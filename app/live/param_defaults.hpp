#pragma once
// The values a freshly booted firmware holds, by parameter id: the rig
// file's [controller] defaults and limits (what the simulator and an image
// built for the rig boot from) and the firmware settings' defaults
// (shared/firmware_settings.hpp). PARAM_DESC carries no default, so
// `params diff` and `params reset` read them here; a firmware built from
// another file may boot with other values, which is why the console says
// where its defaults come from.
#include <cstdint>
#include <map>
#include <vector>

#include "host/rig/rig.hpp"

namespace nlsoft::console {

// Sized by the rig's m and n (per-actuator and per-output parameters).
std::map<uint16_t, std::vector<double>> firmware_defaults(const host::Rig& rig);

}  // namespace nlsoft::console
