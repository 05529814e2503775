#pragma once
// The history length nd = dd chosen from data, not by hand, in two stages.
// 1. MATLAB's arxstruc/selstruc idea: for each length within the capacity,
//    an ARX model fitted by least squares on the training rows, judged by
//    its free run of the rows it was not fitted on (the validation and
//    held-out parts of app/model/pooled_runs.hpp's split); the shortest
//    length within 2 % of the best wins. A linear model stops gaining where
//    its own error floor is (7 samples on the Wiener-Hammerstein data,
//    where a network goes on gaining to 32: 14.5 mV held-out at 12, 3.0 at
//    32), so:
// 2. a network of the widest candidate shape, one seed and a third of the
//    training budget, is trained at the ARX length and at lengths doubling
//    from it up to the capacity, and judged by its free run of the held-out
//    rows; the shortest within 5 % of the best wins (a longer history costs
//    the MCU every step). Nothing here reads a test set.
#include <functional>
#include <string>
#include <vector>

#include "app/model/series.hpp"
#include "app/model/train.hpp"

namespace nlsoft::model {

struct LagTrial {
  int lags = 0;
  double free_run = 0;  // MSE / variance summed over outputs; HUGE_VAL where it diverged or could not be fitted
};

struct LagChoice {
  int lags = 0;
  std::vector<LagTrial> tried;   // stage 1, ARX
  int arx_lags = 0;              // stage 1's choice
  std::vector<LagTrial> probed;  // stage 2, a network's held-out free run per length (empty: not run)
  std::string probe_shape;       // stage 2's network, in words
  std::string words() const;     // "nd = dd = 14: ARX free run ... chose 7; Dense 32 relu ... 7 x, 14 y, 32 z"
};

// Lengths 1..max_lags; `folds` and `validate` as train splits the runs.
// Throws PipelineError when no length leaves rows to fit and judge.
LagChoice search_lags(const std::vector<Series>& runs, int max_lags, int folds, int validate);

// The lengths stage 2 tries from `from`: from, 2 from, 4 from, ... below
// max_lags / sqrt 2, then max_lags (each at least twice the last but the cap).
std::vector<int> probe_lengths(int from, int max_lags);

// Stage 2 on c (stage 1's result): o is the training's options (shape,
// candidates, objective); before_each(lags, what) is told each probe first.
// Returns c unchanged for the one-step objective or when the capacity
// leaves no longer length.
LagChoice probe_network_lags(LagChoice c, const std::vector<Series>& runs, const PlantTarget& target,
                             const TrainOptions& o, int validate, int max_lags,
                             const std::function<void(int lags, const std::string& what)>& before_each);

}  // namespace nlsoft::model
