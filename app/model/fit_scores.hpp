#pragma once
// Judging a predictor on a dataset as system identification does: one-step
// prediction (every row from the measured history) and free-run simulation
// (the y history fed the predictor's own outputs, restarted from the
// measured outputs at each piece of consecutive rows, driven by the data's
// u and l), scored per output as RMSE in the output's unit, nRMSE of its
// span and MATLAB compare's fit % = 100 (1 - |y - yhat| / |y - mean(y)|).
#include <vector>

#include <Eigen/Core>

#include "app/model/arx.hpp"
#include "app/model/dataset.hpp"
#include "app/model/model_store.hpp"

namespace nlsoft::model {

struct Score {
  double rmse = 0;   // the output's unit
  double nrmse = 0;  // a fraction of the output's span (RMSE when the span is not known)
  double fit = 0;    // percent; 100 is perfect, 0 as good as the mean, negative worse
};

// Predictions for the rows of `pieces`, in that order (rows x n).
// k_step (with horizon k > 1, else empty): each row predicted k steps
// ahead, from the measured history k - 1 rows before it and the
// predictor's own outputs since, as the controller predicts over its
// horizon N (paper eq. 3); a row nearer than that to its piece's start is
// predicted from the start.
struct Simulation {
  Eigen::MatrixXd one_step, free_run, k_step;
};

// The network run as the firmware runs it (shared/forward.hpp, float).
// Throws PipelineError when the model's dimensions are not the data's.
Simulation simulate_network(const ModelFile& model, const Dataset& d, const std::vector<RowRange>& pieces,
                            int horizon = 0);
Simulation simulate_arx(const ArxModel& arx, const Dataset& d, const std::vector<RowRange>& pieces, int horizon = 0);

// The measured y(k+1) of the rows of `pieces`, in the order above.
Eigen::MatrixXd measured(const Dataset& d, const std::vector<RowRange>& pieces);

// Per output j, yhat (from a Simulation) against y; span[j] <= 0: nRMSE = RMSE.
std::vector<Score> score(const Eigen::MatrixXd& y, const Eigen::MatrixXd& yhat, const std::vector<double>& span);

}  // namespace nlsoft::model
