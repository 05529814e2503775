#pragma once
// The values a freshly booted firmware holds, by parameter id: the
// platform's preset (shared/platform.hpp) and the firmware settings'
// defaults (shared/firmware_settings.hpp), the very tables the firmware
// boots from. PARAM_DESC carries no default, so `params diff` and
// `params reset` read them here; a firmware built from other sources may
// boot with other values, which is why the console says where its defaults
// come from.
#include <cstdint>
#include <map>
#include <vector>

namespace nlsoft::console {

// Empty when the platform id is not one this console knows. m and n are
// the firmware's dimensions (INFO), which size the per-actuator and
// per-output parameters.
std::map<uint16_t, std::vector<double>> firmware_defaults(uint8_t platform, int m, int n);

}  // namespace nlsoft::console
