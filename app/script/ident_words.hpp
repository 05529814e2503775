#pragma once
// A script's `ident` line as the `ident` command's words (app/live/ident_plan.hpp),
// for the parser's checks and the runner's run.
#include "app/live/ident_plan.hpp"
#include "app/script/script_parser.hpp"

namespace nlsoft::console {

// A script's `ident SIGNAL DURATION key=value...` as the command's words:
// name is the signal, values[0] the duration, options seed, amplitude,
// band, joint, mixed, decimation. Throws CliError for a value that is no number.
IdentWords ident_words(const Command& c);

}  // namespace nlsoft::console
