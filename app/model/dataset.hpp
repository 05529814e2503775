#pragma once
// Preprocessing of the paper's eq. 14: a logged series becomes rows
//   x(k) = [u(k) .. u(k-nd+1) | y(k) .. y(k-dd+1) | l(k)]  ->  label y(k+1)
// in exactly the order the controller builds x at run time
// (shared/input_vector.hpp), then min-max normalisation and the ten-fold
// time-series split. The label y(k+1) is never an input column: the newest
// y in x is y(k).
#include <vector>

#include <Eigen/Core>

#include "app/model/series.hpp"
#include "shared/input_vector.hpp"

namespace nlsoft::model {

// Rows [begin, end) that are consecutive control periods: a free-run
// prediction may run through them without restarting.
struct RowRange {
  long begin = 0, end = 0;
};

struct Dataset {
  InputLayout layout{};
  Eigen::MatrixXd X;  // rows x p, raw units
  Eigen::MatrixXd Y;  // rows x n, y(k+1)
  long first_k = 0;   // series index k of row 0; row r is k = first_k + r (a series without breaks)
  std::vector<RowRange> pieces;  // the rows, cut where the series has a gap
  long rows() const { return static_cast<long>(X.rows()); }
};

// q samples give q - max(nd, dd) rows (k = max(nd,dd)-1 .. q-2), per
// stretch between the series' breaks; a stretch of max(nd, dd) samples or
// fewer gives none. Throws when no stretch gives a row.
Dataset build_dataset(const Series& s, int nd, int dd);

// Rows [begin, end) of d as pieces (each piece of d cut to the range).
std::vector<RowRange> pieces_within(const Dataset& d, long begin, long end);

// Rows [begin, end) of `from` copied into `into` from its row `at` (into's
// X and Y already that long), with their pieces, shifted; returns the
// pieces it added. How runs are stacked into one dataset.
std::vector<RowRange> copy_rows(Dataset& into, long at, const Dataset& from, long begin, long end);

// x_net = (x - in_offset) * in_scale,  y = y_net * out_scale + out_offset
// (+ y(k) when residual), the transform shared/forward.hpp applies.
struct Normalisation {
  Eigen::VectorXd in_offset, in_scale, out_offset, out_scale;
};

struct NormalisationSpec {
  std::vector<double> u_lo, u_hi;  // actuator limits: u columns span at least these
  std::vector<double> y_neutral;   // outputs are centred here (non-residual)
  bool residual = false;
  double out_margin = 1.25;  // targets land in +-1/margin: room inside tanh
};

// Fitted on rows [0, rows) only (the training part), so the test set never
// informs the model. Each u, y and sensor column maps its range to
// [-0.5, 0.5]; every lag of one signal shares one transform. Outputs: the
// largest deviation from the neutral point (or the largest transition
// y(k+1) - y(k) when residual) maps to 1/out_margin.
Normalisation fit_normalisation(const Dataset& d, long rows, const NormalisationSpec& spec);

Eigen::MatrixXd normalise_inputs(const Normalisation& nz, const Eigen::MatrixXd& X);

// sklearn TimeSeriesSplit(n_splits = folds): fold i trains on [0, test_begin)
// and tests on [test_begin, test_begin + rows / (folds + 1)).
struct Fold {
  long test_begin, test_end;
};
std::vector<Fold> time_series_split(long rows, int folds);

// The paper's use of it: the last fold's test chunk is the test set, the
// chunk before it validates (early stopping), the rest trains.
struct Partition {
  long train_end, val_begin, val_end, test_begin, test_end;
};
Partition partition(long rows, int folds = 10);

}  // namespace nlsoft::model
