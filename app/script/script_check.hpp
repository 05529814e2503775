#pragma once
// A parsed script checked whole against the connected firmware before its
// first command runs: a wrong parameter name, element, value count, number
// or range on line 40 should not surface after a ten-minute run on line 3.
// The checks are the ones the commands themselves make (resolve_param,
// parse_param_values, reference_from_spec, the tuner's search space, the
// reference table and parameter file readers), run ahead of time; nothing is
// sent to the firmware but parameter reads.
#include <vector>

#include "app/script/script_parser.hpp"

namespace nlsoft::console {

class LiveConsole;

// Every error found, in line order; empty when the script may run. Left to
// the firmware: rules between parameters (Nc <= N, u_min < u_max), whose
// values the script's own earlier lines may change.
std::vector<ScriptError> check_script(const Script& script, LiveConsole& console);

}  // namespace nlsoft::console
