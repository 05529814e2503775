#pragma once
// A parameter named as a user writes it ("Q", "Q[1]", "Q1") against a
// firmware's parameter list: one reading for every place that takes a name
// (the live console's set and get, the tuner's ranges on a board or on a
// replay's simulator).
#include <string>
#include <utility>

#include "app/link/param_catalog.hpp"

namespace nlsoft::console {

// "Q" -> (Q, -1); "Q[1]" and "Q1" -> (Q, 1). Throws CliError naming the
// known parameters, or the valid element range.
std::pair<ParamInfo, int> resolve_param(const ParamCatalog& catalog, const std::string& name);

}  // namespace nlsoft::console
