#pragma once
// `--set NAME=V[,V...]` (and the script `set` command): text to a validated
// parameter write, with messages that name the parameter, the element and
// the allowed range.
#include <string>
#include <vector>

#include "shared/params.hpp"

namespace nlsoft::console {

struct ParamWrite {
  ParamId id;
  std::vector<float> values;
};

// The one reading of a parameter's typed values, wherever they are typed
// (simulate --set, a script's `set`, the console's edit field, through
// parse_param_values): numbers separated by commas or blanks, each finite
// and what the firmware can hold (float32; whole and >= 0 otherwise); one
// value for a parameter of `count` elements stands for every element.
// Throws CliError naming `name` and what is wrong.
std::vector<double> parse_param_numbers(const std::string& name, const std::vector<std::string>& tokens, size_t count,
                                        bool is_float);

// Parses "Q=1e6,2e6,1e6" for a rig of m inputs and n outputs ("Lambda=0.5":
// 0.5 for every actuator). Throws CliError naming what is wrong.
ParamWrite parse_param_write(const std::string& text, int m, int n);

// Explains a refused write in words ("Q[1] = -2 is out of range [0, 1e+12]").
std::string describe_refusal(const ParamWrite& w, const ParamResult& r, int m, int n);

// Applies every write in order; throws on the first refused one, leaving
// P as it was before that write.
void apply_param_writes(Params<HostCapacity>& P, const std::vector<ParamWrite>& writes, int m, int n);

// "Q, Lambda, s, ..." for error messages.
std::string known_param_names();

}  // namespace nlsoft::console
