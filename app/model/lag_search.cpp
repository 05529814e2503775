#include "app/model/lag_search.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "app/model/arx.hpp"
#include "app/model/error.hpp"
#include "app/model/fit_scores.hpp"
#include "app/model/pooled_runs.hpp"
#include "app/model/train_simulation.hpp"

namespace nlsoft::model {

namespace {

std::string trials(const std::vector<LagTrial>& ts) {
  std::string list;
  for (const LagTrial& t : ts)
    list += (list.empty() ? "" : ", ") + (std::isfinite(t.free_run) ? fmt::format("{} {:.3g}", t.lags, t.free_run)
                                                                    : fmt::format("{} -", t.lags));
  return list;
}

// The shortest length within `slack` of the best; 0 when none is finite.
int shortest_near_best(const std::vector<LagTrial>& ts, double slack) {
  double best = HUGE_VAL;
  for (const LagTrial& t : ts) best = std::min(best, t.free_run);
  if (!std::isfinite(best)) return 0;
  for (const LagTrial& t : ts)
    if (t.free_run <= best * (1 + slack)) return t.lags;
  return 0;
}

}  // namespace

std::string LagChoice::words() const {
  const std::string arx = fmt::format("ARX free run of the rows not fitted on (MSE / variance): {}", trials(tried));
  if (probed.empty()) return fmt::format("nd = dd = {}, chosen by {}", lags, arx);
  return fmt::format("nd = dd = {}, chosen by {} free run of the held-out rows (MSE / variance): {}; from {}, "
                     "which chose {}",
                     lags, probe_shape, trials(probed), arx, arx_lags);
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
  c.lags = c.arx_lags = shortest_near_best(c.tried, 0.02);
  if (c.lags == 0)
    throw PipelineError("no history length from 1 to " + std::to_string(max_lags) +
                        " gives an ARX model a finite free run" + (last_error.empty() ? "" : ": " + last_error));
  return c;
}

std::vector<int> probe_lengths(int from, int max_lags) {
  std::vector<int> out;
  if (from < 1 || from >= max_lags) return out;
  for (int L = from; double(L) < double(max_lags) / std::sqrt(2.0); L *= 2) out.push_back(L);
  if (out.empty() || out.front() != from) out.insert(out.begin(), from);
  out.push_back(max_lags);
  return out;
}

LagChoice probe_network_lags(LagChoice c, const std::vector<Series>& runs, const PlantTarget& target,
                             const TrainOptions& o, int validate, int max_lags,
                             const std::function<void(int lags, const std::string& what)>& before_each) {
  if (o.objective != Objective::Simulation) return c;
  const std::vector<int> lengths = probe_lengths(c.arx_lags, max_lags);
  if (lengths.size() < 2) return c;
  // The widest network shape among the candidates: the one that can use a
  // long history, and the rig's own when its file names one.
  TrainOptions p = o;
  if (!o.keep_shape)
    for (const std::vector<LayerSpec>& alt : o.alternatives)
      if (alt.size() > 1 && alt.front().units > p.layers.front().units) p.layers = alt;
  p.alternatives.clear();
  p.keep_shape = false;
  p.seeds = 1;
  p.epochs = std::min(o.epochs, 50);
  long rows = 0;
  for (const Series& s : runs) rows += s.rows();
  // A third of the L-BFGS budget train_simulation gives the full training.
  p.sim.lbfgs_evals = std::max(20, lbfgs_budget(o.sim, rows) / 3);
  c.probe_shape = describe_layers(p.layers);
  for (int L : lengths) {
    if (o.stop && o.stop->load()) break;
    p.nd = p.dd = L;
    before_each(L, fmt::format("{}, 1 seed, at most {} one-step epochs and {} L-BFGS evaluations", c.probe_shape,
                               p.epochs, p.sim.lbfgs_evals));
    LagTrial t{L, HUGE_VAL};
    try {
      const TrainResult r = train(runs, target, p, validate);
      for (const Candidate& k : r.candidates)
        if (k.is_network() && std::isfinite(k.held_out)) t.free_run = std::min(t.free_run, k.held_out);
    } catch (const PipelineError&) {
      // too few rows at this length: the longer ones have fewer still
    }
    c.probed.push_back(t);
  }
  if (const int L = shortest_near_best(c.probed, 0.05); L > 0) c.lags = L;
  return c;
}

}  // namespace nlsoft::model
