#pragma once
// Text from a user or a database (a run's label, a file name, an
// objective) in a gnuplot script: one escaping function for the language.
#include <string>

namespace nlsoft::console {

// A gnuplot string expression that evaluates to `text`, byte for byte.
// Single-quoted pieces (gnuplot runs a `command` in backquotes even inside
// double quotes, but nothing inside single quotes; a quote is doubled),
// joined by "\n" where the text breaks lines, so a title keeps its lines
// and no line of the text becomes a command.
std::string gnuplot_string(const std::string& text);

}  // namespace nlsoft::console
