#include "app/model/lag_search.hpp"

#include <cmath>

#include <fmt/format.h>

#include "app/model/arx.hpp"
#include "app/model/error.hpp"
#include "app/model/fit_scores.hpp"
#include "app/model/pooled_runs.hpp"

namespace nlsoft::pipeline {

std::string LagChoice::words() const {
  std::string list;
  for (const LagTrial& t : tried)
    list += (list.empty() ? "" : ", ") + (std::isfinite(t.free_run) ? fmt::format("{} {:.3g}", t.lags, t.free_run)
                                                                    : fmt::format("{} -", t.lags));
  return fmt::format("nd = dd = {}, chosen by ARX free run of the rows not fitted on (MSE / variance): {}", lags, list);
}

LagChoice search_lags(const std::vector<Series>& runs, int max_lags, int folds, int validate) {
  LagChoice c;
  std::string last_error;
  for (int L = 1; L <= max_lags; ++L) {
    LagTrial t{L, HUGE_VAL};
    try {
      const Pooled p = pool_runs(runs, L, L, folds, validate);
      const Dataset& d = p.d;
      const ArxModel arx = fit_arx(d, pieces_within(d, 0, p.split.train_end));
      const std::vector<RowRange> judged = pieces_within(d, p.split.val_begin, p.split.test_end);
      const Simulation s = simulate_arx(arx, d, judged);
      const Eigen::MatrixXd y = measured(d, judged);
      const Eigen::MatrixXd yt = d.Y.topRows(p.split.train_end);
      double loss = 0;
      for (Eigen::Index j = 0; j < y.cols(); ++j) {
        const double var = (yt.col(j).array() - yt.col(j).mean()).square().mean();
        const double mse = (s.free_run.col(j) - y.col(j)).squaredNorm() / double(std::max<Eigen::Index>(1, y.rows()));
        loss += mse / (var > 0 ? var : 1.0);
      }
      if (std::isfinite(loss)) t.free_run = loss;
    } catch (const PipelineError& e) {
      last_error = e.what();  // too few rows for this length: longer ones have fewer still
    }
    c.tried.push_back(t);
  }
  double best = HUGE_VAL;
  for (const LagTrial& t : c.tried) best = std::min(best, t.free_run);
  if (!std::isfinite(best))
    throw PipelineError("no history length from 1 to " + std::to_string(max_lags) +
                        " gives an ARX model a finite free run" + (last_error.empty() ? "" : ": " + last_error));
  for (const LagTrial& t : c.tried)
    if (t.free_run <= best * 1.02) {
      c.lags = t.lags;
      break;
    }
  return c;
}

}  // namespace nlsoft::pipeline
