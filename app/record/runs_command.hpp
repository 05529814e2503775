#pragma once
// `nlsoft-console runs list|show|export|compare`: the recordings, offline.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_runs_command(CLI::App& app);

}  // namespace nlsoft::console
