#pragma once
// `nlsoft-console runs replay ID`: a recorded run of the simulator run
// again, step for step, with changes (app/replay/).
#include <CLI/CLI.hpp>

namespace nlsoft::console {

// Adds `replay` to the `runs` command.
void add_replay_command(CLI::App& runs);

}  // namespace nlsoft::console
