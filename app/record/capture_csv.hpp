#pragma once
// An external measurement of a rig's outputs (motion capture, a camera
// tracker) as a CSV file: a header `time,y0,y1,...` (or the rig's output
// names, in any order), then one row per capture frame, time in seconds on
// the capture's own clock. Read whole and checked before anything uses it.
#include <string>
#include <vector>

namespace nlsoft::console {

struct Capture {
  std::string path;
  int n = 0;
  std::vector<double> t;     // seconds, capture clock, strictly increasing
  std::vector<double> y;     // rows of n, in the run's output order
  std::vector<long> line;    // each row's line in the file, for messages
  size_t rows() const { return t.size(); }
};

// Throws CliError (exit 2) naming file:line: a header that lacks an output
// or has a column no output is named for, a cell that is not a finite
// number (NaN, inf, empty), a row of the wrong width, a time not after the
// previous row's, fewer than two rows. `names` are the rig's output names
// (may be empty: then only y0..y{n-1} are accepted).
Capture read_capture(const std::string& path, int n, const std::vector<std::string>& names);

}  // namespace nlsoft::console
