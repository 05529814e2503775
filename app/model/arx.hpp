#pragma once
// The linear baseline system identification judges a network against: an
// ARX model on the network's own input vector (u lags nd, y lags dd, the
// sensors l), y(k+1) = [x(k) 1] * theta, fitted by least squares. A network
// that does not beat it on free-run prediction has learnt nothing a matrix
// could not. Kept in the model file's fit section (JSON), beside the
// network, so the network's bytes and hash stay what they were.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "app/model/dataset.hpp"

namespace nlsoft::model {

struct ArxModel {
  InputLayout layout{};
  Eigen::MatrixXd theta;  // (p + 1) x n: one column per output, the bias last

  // y(k+1) for one input vector x (p values, physical units).
  void predict(const double* x, double* y) const;
};

// Least squares over the rows of `pieces` (column-pivoting QR: the lags of
// one signal are nearly collinear at a fast control rate). Throws
// PipelineError when there are fewer rows than coefficients.
ArxModel fit_arx(const Dataset& d, const std::vector<RowRange>& pieces);

// JSON text and back; arx_from_json throws PipelineError naming `where`.
std::string arx_to_json(const ArxModel& a);
ArxModel arx_from_json(const std::string& text, const std::string& where);

}  // namespace nlsoft::model
