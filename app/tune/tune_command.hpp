#pragma once
// `nlsoft-console tune`: connect (a port, --sim or --qemu), run a tuning
// session headless, print and save the best set. Registered on the main app.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_tune_command(CLI::App& app);

}  // namespace nlsoft::console
