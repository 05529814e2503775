#pragma once
// `nlsoft-console ident (--sim RIG | --qemu RIG | PORT) --signal prbs
// --duration 10min`: an identification run (protocol 1.3) recorded into the
// runs database, what a model of the rig is trained from.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_ident_command(CLI::App& app);

}  // namespace nlsoft::console
