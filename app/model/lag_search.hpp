#pragma once
// The history length nd = dd chosen from data, not by hand (MATLAB's
// arxstruc/selstruc idea): for each length within the capacity, an ARX
// model fitted by least squares on the training rows, judged by its free
// run of the rows it was not fitted on (the validation and held-out parts
// of app/model/pooled_runs.hpp's split). The shortest length whose free run
// is within 2 % of the best is chosen: a longer history costs the MCU
// every step and fits noise. The network then trains on the chosen length.
#include <string>
#include <vector>

#include "app/model/series.hpp"

namespace nlsoft::pipeline {

struct LagTrial {
  int lags = 0;
  double free_run = 0;  // MSE / variance summed over outputs; HUGE_VAL where it diverged or could not be fitted
};

struct LagChoice {
  int lags = 0;
  std::vector<LagTrial> tried;
  std::string words() const;  // "nd = dd = 3, chosen by ARX free run of the rows not fitted on over 1..20"
};

// Lengths 1..max_lags; `folds` and `validate` as train splits the runs.
// Throws PipelineError when no length leaves rows to fit and judge.
LagChoice search_lags(const std::vector<Series>& runs, int max_lags, int folds, int validate);

}  // namespace nlsoft::pipeline
