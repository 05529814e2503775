#pragma once
// The rows every model is fitted, stopped and chosen on: each run split as
// one series is (the ten-fold time-series split: its last part is held
// out, the part before validates), the parts of all runs pooled, training
// parts first. With `validate` >= 0 that run is held out whole and the
// others keep their last part for validation.
#include <string>
#include <vector>

#include "app/model/dataset.hpp"
#include "app/model/series.hpp"

namespace nlsoft::model {

struct Pooled {
  Dataset d;
  Partition split{};
  std::vector<RowRange> test_pieces;  // the held-out rows, as pieces of consecutive rows
  std::string held_out;               // which rows those are, in words
};

// Throws PipelineError, naming the run, when a run is too short for `folds`.
Pooled pool_runs(const std::vector<Series>& runs, int nd, int dd, int folds, int validate);

}  // namespace nlsoft::model
