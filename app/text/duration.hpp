#pragma once
// A duration as a user types it ("5s", "250ms", "2min", "1.5h"): script
// lines, tune's words and options, ident's --duration, runs list --since.
#include <string>

namespace nlsoft::console::text {

// Seconds, > 0 and at most 30 days; throws std::invalid_argument in words
// ("'ten' is not a duration (e.g. 5s, 250ms, 2min)").
double parse_duration(const std::string& text);

}  // namespace nlsoft::console::text
