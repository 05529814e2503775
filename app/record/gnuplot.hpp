#pragma once
// Drawing with gnuplot, run as a subprocess. Why gnuplot: it is a
// well-kept plotting program packaged by Debian (gnuplot-nox, no X needed)
// whose SVG and cairo PNG terminals already do axes, ticks, legends and
// multi-panel layouts; driven through a script it keeps the console free of
// a plotting library's build and ABI, and a machine without it loses only
// `runs plot`, with a message that says what to install.
#include <string>

namespace nlsoft::console {

// Runs gnuplot (`$NLSOFT_GNUPLOT`, else `gnuplot` on PATH) on `script` and
// returns what it wrote to standard output: the image. Throws CliError when
// gnuplot is missing or fails, with what it said.
std::string run_gnuplot(const std::string& script);

}  // namespace nlsoft::console
