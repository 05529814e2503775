#pragma once
// Tracking metrics of a run: the figures the paper reports and the console
// compares runs by.
#include <limits>
#include <vector>

#include "shared/reference.hpp"

namespace nlsoft::console {

struct TrackingMetrics {
  std::vector<double> rmse;  // per axis, y_true vs y_ref
  double nrmse = 0;          // max RMSE / max range of the reference, tracked axes (NaN: flat reference)
  double nrmse_all = 0;      // the same over every axis
  std::vector<int> tracked;  // the axes nrmse covers
  double max_error = 0;      // largest Euclidean distance y_true - y_ref
  double mean_iterations = 0;
  double solve_p50_us = 0, solve_p99_us = 0;
};

// Rows of n: y_ref, y (true or predicted). An axis whose weight (Q) is below
// 1e-3 of the largest is one the tuning deliberately leaves untracked (the
// paper's tendon Q = diag(1e-3, 5e3, 2e3): the depth y0 follows y1, y2 on
// the rig's surface): it is kept in rmse but left out of nrmse and max_error.
// Pass nullptr to use every axis; nrmse_all always does.
TrackingMetrics tracking_metrics(const std::vector<float>& y_ref, const std::vector<float>& y, int n,
                                 const float* weight = nullptr);

// How hard the actuators worked, from rows of m inputs (the one computation
// behind `runs` metrics, `tune`'s objective and `simulate`):
struct InputMetrics {
  // The RMS of the per-step input change, each actuator over its range
  // u_max - u_min (what Lambda penalises; raw units when the limits are not
  // known). 0 with fewer than two rows.
  double u_effort = 0;
  // Share of actuator-time spent within 1 % of its range of a limit (the
  // mean of saturated_per_input); NaN when the limits are not known.
  double u_saturated = std::numeric_limits<double>::quiet_NaN();
  // Each actuator's share of steps within 1 % of its range of a limit
  // (empty when the limits are not known): an antagonistic pair (HASEL)
  // keeps one side at its lower limit by design, a single input pinned at
  // a limit most of the run is clipping, not tracking.
  std::vector<double> saturated_per_input;
};
// lo, hi: u_min, u_max per actuator (empty when not known).
InputMetrics input_metrics(const std::vector<float>& u, int m, const std::vector<float>& lo,
                           const std::vector<float>& hi);

// p in [0, 1] of a sample (copied, not modified).
double percentile(std::vector<float> v, double p);

// The paper's step-response figures for one level of a Step reference.
struct StepResponse {
  double from = 0, to = 0;        // reference levels
  double rise_s = -1;             // 0 -> 90 % of the change; -1 if never reached
  double overshoot_pct = 0;       // past `to`, in % of |to - from|
  double steady_error = 0;        // |mean over 80-90 % of the segment - to|
};

// y: one axis of the trace (row k = after u(k)), dt: control period.
std::vector<StepResponse> step_responses(const RefParams& ref, const std::vector<float>& y, int n, int axis,
                                         float dt);

}  // namespace nlsoft::console
