#pragma once
// What the console says about a parameter beyond PARAM_DESC. The firmware
// describes each parameter by name, type, element count, range and unit;
// what a parameter means and what its options are called lives here, keyed
// by name, so a firmware with other parameters still gets an editor (just
// without these words). The same names are accepted as values:
// `set mode fd`, `set safe_state hold`.
#include <string>
#include <vector>

#include "app/link/param_catalog.hpp"

namespace nlsoft::console {

struct ParamOption {
  const char* name;
  double value;
};

// One sentence on what the parameter does to the controller; "" for a name
// the console does not know.
std::string param_description(const std::string& name);

// The named values of an option parameter (mode, feedback, safe_state);
// empty for the others.
const std::vector<ParamOption>& param_options(const std::string& name);

// "exact (0), fd (1)".
std::string param_options_text(const std::string& name);

// Typed values to what parse_param_values takes: option names become their
// numbers (one value for a parameter of several elements is that value for
// every element: parse_param_values, as simulate --set reads it). A word that is neither a number nor
// an option throws CliError listing the options.
std::vector<std::string> expand_param_tokens(const ParamInfo& p, const std::vector<std::string>& tokens);

// Values with their option names where they have one: "1 (fd)".
std::string format_param_named(const ParamInfo& p, const std::vector<double>& values);

// "range [0, 1e+12] 1/u^2, 6 values (one sets all)".
std::string param_range_text(const ParamInfo& p);

}  // namespace nlsoft::console
