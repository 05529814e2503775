#pragma once
// The interactive console (ncursesw): plots, parameter panel, references,
// run control, runs browser, `:` command line. Returns the exit code.
#include "app/live/live_console.hpp"

namespace nlsoft::console {

int run_tui(LiveConsole& console);

}  // namespace nlsoft::console
