#pragma once
// Lining an external capture of a run's outputs up with the run: the
// capture's clock has an unknown offset from the run's, estimated here from
// the run's own recorded signals, and the capture is then interpolated onto
// the run's sample times.
#include <vector>

#include "app/record/capture_csv.hpp"

namespace nlsoft::console {

// What the run recorded, on its own clock: t[k] = the sample's control step
// over the loop rate (seconds since the run's first step), u rows of m,
// l rows of w (w = 0: no sensors).
struct RunSignals {
  int m = 0, w = 0;
  std::vector<double> t;
  std::vector<double> u, l;
  size_t rows() const { return t.size(); }
};

struct OffsetEstimate {
  double offset_s = 0;  // run time = capture time - offset_s
  double score = 0;     // the innovation the run's signals explain at that offset, per run sample, over the outputs' variance
};

// Throws CliError when no offset leaves the capture over at least half of
// the shorter of the two spans (nothing to estimate from), or when the
// capture is too long to search every offset of (over 2^22 points at the
// run's rate).
OffsetEstimate estimate_offset(const RunSignals& run, const Capture& cap);

// The capture at each run sample (run time t[k] is capture time
// t[k] + offset_s), linearly interpolated; NaN where the capture does not
// reach. Rows of cap.n.
std::vector<double> resample(const Capture& cap, const std::vector<double>& run_t, double offset_s);

}  // namespace nlsoft::console
