#pragma once
// `nlsoft-console simulate`: plant + controller on the host, tracking metrics
// and, with --svg/--png, the picture `runs plot` draws of a recorded run.
#include <CLI/CLI.hpp>

#include "app/simulate/simulation_picture.hpp"

namespace nlsoft::console {

// plot: draws --svg/--png as `runs plot` draws a recorded run; without it
// those options say this build cannot draw.
void add_simulate_command(CLI::App& app, SimulationPlotter plot = {});

}  // namespace nlsoft::console
