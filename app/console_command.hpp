#pragma once
// The console itself, what `nlsoft-console` runs without a subcommand:
// `nlsoft-console PORT`, `--sim PLATFORM`, `--script FILE`. Its options and
// its callback go on the main app (main.cpp). Beside main.cpp, above the
// rooms it starts: the live console (live/), then the TUI (tui/) or a
// script (script/).
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_live_console(CLI::App& app);

}  // namespace nlsoft::console
