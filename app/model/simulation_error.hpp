#pragma once
// The simulation objective: the network fed its own predictions, as the
// controller feeds it over its horizon and as free-run fit judges it.
// A window starts at a row with the measured history; for H steps the u and
// sensor columns stay measured while the y-history columns hold the
// network's own earlier outputs (the roll of Algorithm 1). The loss is the
// mean squared error of those H predictions, each output weighted by the
// inverse of its variance; the gradient is exact, carried back through the
// recursion (truncated back-propagation through time: Forgione & Piga 2021,
// "truncated simulation error"; MATLAB nlarx's Focus = 'simulation').
#include <vector>

#include <Eigen/Core>

#include "app/model/dataset.hpp"
#include "app/model/network.hpp"

namespace nlsoft::model {

// Row-major: the recursion reads one row per window and step, and a row of
// a column-major matrix of 100 000 rows is one cache miss per column (a
// quarter of `train`'s time went to that copy). Same values, same sums.
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// What the recursion needs of the data, in the network's units.
struct SimulationData {
  InputLayout layout{};
  RowMajorMatrix Xn;                   // rows x p, normalised measured inputs
  RowMajorMatrix Y;                    // rows x n, measured y(k+1), physical units
  Eigen::VectorXd y_in_offset, y_in_scale;  // n: how a y-history column is normalised (every lag alike)
  Eigen::VectorXd out_offset, out_scale;    // n: y = out * scale + offset (+ y(k) when residual)
  Eigen::VectorXd weight;              // n: 1 / variance of each output over the training rows
  bool residual = false;
};

// Windows of H rows starting at `starts`, all inside one piece each. Returns
// the mean over windows, steps and outputs of weight_j (y^ - y)^2, and adds
// its gradient to *grad (param_count long) unless null. Non-finite when the
// recursion blows up.
double simulation_loss(const Network& net, const SimulationData& s, const std::vector<long>& starts, int H,
                       std::vector<double>* grad);

// Free run over each piece from its measured start (as evaluate() runs the
// exported model): the weighted mean squared error over all their rows;
// +inf when the run blows up.
double free_run_loss(const Network& net, const SimulationData& s, const std::vector<RowRange>& pieces);

// The starts of windows of H rows inside `pieces`, every `stride` rows from
// `offset` (0 <= offset < stride) in each piece. A piece shorter than H
// gives none (its rows still train the one-step warm start).
std::vector<long> window_starts(const std::vector<RowRange>& pieces, int H, int stride, int offset);

}  // namespace nlsoft::model
