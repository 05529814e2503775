#pragma once
// `nlsoft-console ports [--json]`: the serial ports, what looks like a
// board on them (an ST-LINK, a Teensy) and which are busy, and by whom.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_ports_command(CLI::App& app);

}  // namespace nlsoft::console
