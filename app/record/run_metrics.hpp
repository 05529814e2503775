#pragma once
// Per-run figures (what `runs show`, `runs compare`, `expect` and `sweep`
// speak of), computed from recorded samples with app/metrics/tracking_metrics.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "app/metrics/tracking_metrics.hpp"
#include "app/record/run_store.hpp"

namespace nlsoft::console {

struct RunMetrics {
  uint64_t samples = 0;
  double duration_s = 0;  // the time the samples span (firmware clock)
  double wall_s = 0;      // start to end of the run (console clock); 0 while unfinished
  bool has_true = false;
  TrackingMetrics truth;      // y_true vs y_ref (when the firmware sends y_true)
  TrackingMetrics predicted;  // y_hat vs y_ref
  // Worst tracked axis's RMSE over that axis's task-space size (true output
  // when sent, else predicted): defined for holds and steps too. NaN on a
  // platform whose task space the console does not know.
  double nrmse_space = std::numeric_limits<double>::quiet_NaN();
  // How far the reference and the tracked output (true when sent, else
  // predicted) move over the rows measured, per axis (max - min): a window
  // in which the reference barely moves makes nrmse a measure of noise.
  std::vector<double> ref_span, y_span;
  double loop_rate_hz = 0;    // from step and time stamps; nominal if those are missing
  double loop_rate_set_hz = 0;     // the firmware's nominal rate (INFO), the one the run was set to
  bool loop_rate_measured = false;  // loop_rate_hz came from the stamps (app/record/loop_rate.hpp)
  double compute_p50_us = 0, compute_p99_us = 0;
  double mean_iterations = 0;
  uint64_t lost_frames = 0;
  uint64_t gaps = 0;
  // How hard the actuators worked: the RMS of the per-step input change,
  // each actuator over its range u_max - u_min (what Lambda penalises; raw
  // units when the limits are not known). 0 without u.
  double u_effort = 0;
  // Share of actuator-time spent within 1 % of its range of a limit (the
  // mean over actuators of each one's share of samples there): a controller
  // pinned against its limits is clipping, not tracking. Per actuator, not
  // "any actuator", since an antagonistic pair (HASEL) keeps one side at
  // its lower limit, off, by design. NaN when the limits are not known.
  double u_saturated = std::numeric_limits<double>::quiet_NaN();
};

// The input limits in force at a run's start (u_min, u_max per actuator);
// empty when not recorded.
struct InputLimits {
  std::vector<float> lo, hi;
};

// weights: per-axis Q at the start of the run (empty: every axis counts);
// axes weighted ~0 relative to the largest are left out of nrmse/max_error.
RunMetrics run_metrics(const RunRow& run, const RunSeries& s, const std::vector<float>& weights, uint64_t gaps,
                       const InputLimits& limits = {});

// Loads and computes in one go; skip_s leaves out the run's first seconds
// (a sweep row's settling time) from every figure but the totals of lost
// frames and gaps; window_s > 0 ends the figures that long after skip_s, so
// runs that overshot their duration (a fast simulator outruns the console's
// polling) are measured over the same span.
RunMetrics run_metrics(RunStore& store, int64_t run_id, double skip_s = 0, double window_s = 0);

// Said wherever a run's tracking figures are shown and the run has no
// measured output (no y_true: a rig whose outputs nothing measures): its
// nrmse and rmse then say how well the controller followed its own model,
// not how the rig moved.
inline constexpr const char* kNoMeasuredOutput = "no measured output: tracking scored on the model's prediction";

// nrmse as printed: "0.0123", with `percent` "0.0123 (1.23 %)"; a
// reference that held still over the run (a run shorter than its hold) has
// no range to normalise by, which is said instead of "nan".
std::string nrmse_words(double nrmse, bool percent = false);

// One vocabulary for every metric the console prints (CONSOLE.md,
// "Metrics"): the names `expect`, `sweep` and `tune` accept and the keys of
// `runs ... --json` and `simulate --json`. A name carries its unit when it
// has one: rmse (worst axis), rmse0.., nrmse, nrmse_space, max_error,
// rmse_hat, nrmse_hat, lost_frames, loop_rate_hz, compute_p50_us,
// compute_p99_us, iterations, samples, duration_s, wall_s, gaps, u_effort,
// u_saturated.
const std::vector<std::string>& metric_names();
// The short spellings (lost, loop_rate, compute_p50, compute_p99, duration,
// wall) are read as the names above, so older scripts keep working.
std::string canonical_metric_name(const std::string& name);
// A name metric_value() knows (any rmseK included), in either spelling.
bool known_metric(const std::string& name);
std::optional<double> metric_value(const RunMetrics& m, const std::string& name);

}  // namespace nlsoft::console
