#include "app/model/fit_scores.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "app/model/error.hpp"
#include "shared/forward.hpp"

namespace nlsoft::model {
namespace {

long count_rows(const std::vector<RowRange>& pieces) {
  long rows = 0;
  for (const RowRange& p : pieces) rows += std::max(0L, p.end - p.begin);
  return rows;
}

// One pass over the pieces for any predictor step(x, y) (T: its number
// type); the free run's y history lives in its own copy of x.
// Feeds the newest output y into the history queue yq (dd outputs, newest first).
template <class T>
void shift_in(std::vector<T>& yq, const T* y, const InputLayout& L) {
  for (int i = L.dd * L.n - 1; i >= L.n; --i) yq[size_t(i)] = yq[size_t(i - L.n)];
  for (int j = 0; j < L.n; ++j) yq[size_t(j)] = y[j];
}

template <class T, class Step>
Simulation run(const Dataset& d, const std::vector<RowRange>& pieces, int horizon, Step step) {
  const InputLayout& L = d.layout;
  const long rows = count_rows(pieces);
  Simulation s;
  s.one_step.resize(rows, L.n);
  s.free_run.resize(rows, L.n);
  if (horizon > 1) s.k_step.resize(rows, L.n);
  std::vector<T> x(size_t(L.p())), y(size_t(L.n)), yq(size_t(L.dd * L.n)), kq(yq.size());
  // Row r of X holds the measured history its prediction starts from.
  const auto history = [&](std::vector<T>& q, long r) {
    for (int i = 0; i < L.dd * L.n; ++i) q[size_t(i)] = T(d.X(r, L.y_begin() + i));
  };
  long out = 0;
  for (const RowRange& piece : pieces) {
    if (piece.end <= piece.begin) continue;
    history(yq, piece.begin);
    for (long r = piece.begin; r < piece.end; ++r, ++out) {
      for (int i = 0; i < L.p(); ++i) x[size_t(i)] = T(d.X(r, i));
      step(x.data(), y.data());
      for (int j = 0; j < L.n; ++j) s.one_step(out, j) = double(y[size_t(j)]);
      for (int i = 0; i < L.dd * L.n; ++i) x[size_t(L.y_begin() + i)] = yq[size_t(i)];
      step(x.data(), y.data());
      for (int j = 0; j < L.n; ++j) s.free_run(out, j) = double(y[size_t(j)]);
      shift_in(yq, y.data(), L);
      if (horizon <= 1) continue;
      const long from = std::max(piece.begin, r - horizon + 1);
      history(kq, from);
      for (long q = from; q <= r; ++q) {
        for (int i = 0; i < L.p(); ++i) x[size_t(i)] = T(d.X(q, i));
        for (int i = 0; i < L.dd * L.n; ++i) x[size_t(L.y_begin() + i)] = kq[size_t(i)];
        step(x.data(), y.data());
        shift_in(kq, y.data(), L);
      }
      for (int j = 0; j < L.n; ++j) s.k_step(out, j) = double(y[size_t(j)]);
    }
  }
  return s;
}

void check_layout(const InputLayout& a, const InputLayout& d, const char* what) {
  if (a.m != d.m || a.n != d.n || a.w != d.w || a.nd != d.nd || a.dd != d.dd)
    throw PipelineError(std::string("the ") + what + "'s dimensions (m=" + std::to_string(a.m) + " n=" +
                        std::to_string(a.n) + " w=" + std::to_string(a.w) + " nd=" + std::to_string(a.nd) + " dd=" +
                        std::to_string(a.dd) + ") are not the data's (m=" + std::to_string(d.m) + " n=" +
                        std::to_string(d.n) + " w=" + std::to_string(d.w) + " nd=" + std::to_string(d.nd) +
                        " dd=" + std::to_string(d.dd) + ")");
}

}  // namespace

Simulation simulate_network(const ModelFile& model, const Dataset& d, const std::vector<RowRange>& pieces,
                            int horizon) {
  const Model<HostCapacity> M = model.view();
  check_layout(InputLayout{M.m, M.n, M.w, M.nd, M.dd}, d.layout, "model");
  ForwardScratch<HostCapacity, float> scratch;
  return run<float>(d, pieces, horizon, [&](const float* x, float* y) { forward(M, x, y, scratch); });
}

Simulation simulate_arx(const ArxModel& arx, const Dataset& d, const std::vector<RowRange>& pieces, int horizon) {
  check_layout(arx.layout, d.layout, "ARX baseline");
  return run<double>(d, pieces, horizon, [&](const double* x, double* y) { arx.predict(x, y); });
}

Eigen::MatrixXd measured(const Dataset& d, const std::vector<RowRange>& pieces) {
  Eigen::MatrixXd y(count_rows(pieces), d.layout.n);
  long at = 0;
  for (const RowRange& p : pieces) {
    const long len = p.end - p.begin;
    if (len <= 0) continue;
    y.middleRows(at, len) = d.Y.middleRows(p.begin, len);
    at += len;
  }
  return y;
}

std::vector<Score> score(const Eigen::MatrixXd& y, const Eigen::MatrixXd& yhat, const std::vector<double>& span) {
  std::vector<Score> out(size_t(y.cols()));
  const double rows = double(y.rows());
  if (y.rows() == 0) return out;
  for (Eigen::Index j = 0; j < y.cols(); ++j) {
    const double err = (y.col(j) - yhat.col(j)).norm();
    const double spread = (y.col(j).array() - y.col(j).mean()).matrix().norm();
    Score& s = out[size_t(j)];
    s.rmse = err / std::sqrt(rows);
    const double sp = size_t(j) < span.size() ? span[size_t(j)] : 0.0;
    s.nrmse = sp > 0 ? s.rmse / sp : s.rmse;
    // A constant output has no spread to explain: fit is undefined (NaN).
    s.fit = spread > 0 ? 100.0 * (1.0 - err / spread) : std::nan("");
  }
  return out;
}

}  // namespace nlsoft::model
