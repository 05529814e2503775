#pragma once
// Tab at the `:` line: what the word at the cursor can become. Commands
// first; then, after set/get/sweep, the firmware's parameter names; after a
// parameter with named options, those; after plot, the plot signals; after
// ref, the reference kinds.
#include <string>
#include <vector>

namespace nlsoft::console::tui {

struct Completion {
  std::string text;                     // the line with the word completed (as far as it is unambiguous)
  std::vector<std::string> candidates;  // what the word could still be, when more than one
};

// `line` is what is left of the cursor; `params` the firmware's parameter
// names.
Completion complete_command(const std::string& line, const std::vector<std::string>& params);

}  // namespace nlsoft::console::tui
