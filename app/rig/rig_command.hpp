#pragma once
// `nlsoft-console rig check NAME|PATH` and `rig list`.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_rig_command(CLI::App& app);

}  // namespace nlsoft::console
