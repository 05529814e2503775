#pragma once
// `nlsoft-console simulate`: plant + controller on the host, tracking metrics.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_simulate_command(CLI::App& app);

}  // namespace nlsoft::console
