#pragma once
// The top-level console invocation: `nlsoft-console PORT`, `--sim PLATFORM`,
// `--script FILE`, plus the `runs` subcommand. Registered on the main app.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_console_commands(CLI::App& app);

}  // namespace nlsoft::console
