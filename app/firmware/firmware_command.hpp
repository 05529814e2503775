#pragma once
// `nlsoft-console firmware build --rig FILE --board BOARD`: a rig's
// Cortex-M images, built from its rig file (image_build.hpp).
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_firmware_command(CLI::App& app);

}  // namespace nlsoft::console
