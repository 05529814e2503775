#include "app/model/train_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include <LBFGS.h>

#include "app/model/adam.hpp"
#include "app/model/random.hpp"
#include "shared/fixed_math.hpp"

namespace nlsoft::model {
namespace {

constexpr double kPi = 3.141592653589793;

bool stopped(const SimulationOptions& o) { return o.stop && o.stop->load(std::memory_order_relaxed); }

// The full-batch objective on two threads: the windows split in halves,
// each half's gradient summed into one (the loss is a mean, so each half is
// weighted by its share of the windows).
double parallel_loss(const Network& net, const SimulationData& s, const std::vector<long>& starts, int H,
                     int threads, std::vector<double>& grad) {
  const size_t half = starts.size() / 2;
  grad.assign(net.param_count(), 0.0);
  if (threads < 2 || half < 8) return simulation_loss(net, s, starts, H, &grad);
  const std::vector<long> a(starts.begin(), starts.begin() + long(half)), b(starts.begin() + long(half), starts.end());
  std::vector<double> gb(net.param_count(), 0.0);
  double lb = 0.0;
  std::thread other([&] { lb = simulation_loss(net, s, b, H, &gb); });
  const double la = simulation_loss(net, s, a, H, &grad);
  other.join();
  const double wa = double(a.size()) / double(starts.size()), wb = 1.0 - wa;
  for (size_t k = 0; k < grad.size(); ++k) grad[k] = wa * grad[k] + wb * gb[k];
  return wa * la + wb * lb;
}

struct Best {
  double val = std::numeric_limits<double>::infinity();
  std::vector<double> theta;
  void offer(double v, const std::vector<double>& th) {
    if (v < val) val = v, theta = th;
  }
};

}  // namespace

int lbfgs_budget(const SimulationOptions& o, long rows) {
  return o.lbfgs_evals >= 0 ? o.lbfgs_evals : int(std::clamp<long>(15000000L / std::max(1L, rows), 50L, 2000L));
}

namespace {

// Adam over windows that start at a random offset each epoch, so every
// row is a window's first step in some epoch; the weights end as the best.
void adam_epochs(Network& net, const SimulationData& s, const std::vector<RowRange>& train,
                 const std::vector<RowRange>& val, const SimulationOptions& o, int H, const SimulationProgress& progress,
                 Best& best, SimulationReport& rep) {
  std::vector<double>& th = net.theta();
  Random rng(o.seed ^ 0x5157u);
  Adam adam(th.size());
  std::vector<double> grad;
  int since_best = 0;
  for (int epoch = 1; epoch <= o.epochs && !stopped(o); ++epoch) {
    std::vector<long> starts = window_starts(train, H, H, int(rng.integer(0, H - 1)));
    if (starts.empty()) starts = window_starts(train, H, H, 0);
    for (long i = long(starts.size()) - 1; i > 0; --i) std::swap(starts[size_t(i)], starts[size_t(rng.integer(0, i))]);
    const double lr = 0.5 * o.lr * (1.0 + fixed_math::cos(kPi * (epoch - 1) / o.epochs));
    double sum = 0.0;
    long batches = 0;
    std::vector<long> batch;
    for (size_t at = 0; at < starts.size(); at += size_t(o.batch)) {
      batch.assign(starts.begin() + long(at), starts.begin() + long(std::min(starts.size(), at + size_t(o.batch))));
      grad.assign(th.size(), 0.0);
      const double l = simulation_loss(net, s, batch, H, &grad);
      if (!std::isfinite(l)) continue;  // a window that blew up teaches nothing; the next batch may
      // Clipping keeps one exploding window from throwing the weights out
      // of the region the warm start found.
      double norm = 0.0;
      for (double g : grad) norm += g * g;
      norm = std::sqrt(norm);
      adam.step(th, grad, lr, norm > 1.0 ? 1.0 / norm : 1.0);
      sum += l;
      ++batches;
    }
    const double v = free_run_loss(net, s, val);
    const double before = best.val;
    best.offer(v, th);
    since_best = best.val < before ? 0 : since_best + 1;
    rep.epochs = epoch;
    if (progress) progress("simulation", epoch, o.epochs, batches ? sum / double(batches) : 0.0, v, best.val);
    if (since_best >= o.patience) break;
  }
  th = best.theta;
}

// L-BFGS from the best weights on windows laid end to end. LBFGS++ rather than NLopt's
// LD_LBFGS: its backtracking line search steps back from a trial point
// whose recursion blew up (+inf), where NLopt's gives up ("nlopt
// failure") at the first one. The validation rows are simulated at every
// tenth new lowest training loss: the weights that simulate them best are
// kept, and 20 such checks without a better one end the search.
void lbfgs(Network& net, const SimulationData& s, const std::vector<RowRange>& train, const std::vector<RowRange>& val,
           const SimulationOptions& o, int H, const SimulationProgress& progress, Best& best, SimulationReport& rep) {
  std::vector<double>& th = net.theta();
  long rows = 0;
  for (const RowRange& r : train) rows += r.end - r.begin;
  const int budget = lbfgs_budget(o, rows);
  if (budget <= 0 || stopped(o)) return;
  const std::vector<long> starts = window_starts(train, H, H, 0);
  struct Halt {};
  double lowest = std::numeric_limits<double>::infinity();
  int improvements = 0, checks_since_best = 0;
  std::vector<double> full;
  auto objective = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) -> double {
    if (stopped(o) || rep.evals >= budget || checks_since_best >= 20) throw Halt{};
    th.assign(x.data(), x.data() + x.size());
    const double l = parallel_loss(net, s, starts, H, o.threads, full);
    ++rep.evals;
    if (!std::isfinite(l)) return std::numeric_limits<double>::infinity();  // the line search backs off
    g = Eigen::Map<const Eigen::VectorXd>(full.data(), Eigen::Index(full.size()));
    if (l < lowest) {
      lowest = l;
      if (++improvements % 10 == 0) {
        const double v = free_run_loss(net, s, val);
        const double before = best.val;
        best.offer(v, th);
        checks_since_best = best.val < before ? 0 : checks_since_best + 1;
        if (progress) progress("L-BFGS", rep.evals, budget, l, v, best.val);
      }
    }
    return l;
  };
  LBFGSpp::LBFGSParam<double> param;
  param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_WOLFE;
  param.epsilon = 1e-9;
  param.epsilon_rel = 1e-9;
  param.max_linesearch = 40;
  LBFGSpp::LBFGSSolver<double> solver(param);
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(best.theta.data(), Eigen::Index(best.theta.size()));
  double fx = 0.0;
  try {
    solver.minimize(objective, x, fx);
  } catch (const Halt&) {
  } catch (const std::exception&) {
    // A line search that found no lower point (converged as far as
    // doubles tell): the weights judged so far stand.
  }
  // The last point with the lowest training loss is judged too.
  const double v = free_run_loss(net, s, val);
  best.offer(v, th);
  th = best.theta;
}

}  // namespace

SimulationReport fit_simulation(Network& net, const SimulationData& s, const std::vector<RowRange>& train,
                                const std::vector<RowRange>& val, const SimulationOptions& o,
                                const SimulationProgress& progress) {
  SimulationReport rep;
  std::vector<double>& th = net.theta();
  Best best;
  rep.start_val = free_run_loss(net, s, val);
  // The start stands until a finite free run beats it. A start whose free
  // run blew up (a least-squares map that diverges on the validation rows,
  // as one fitted on closed-loop runs can) is kept as the weights all the
  // same: an empty set would leave the network without any.
  best.theta = th;
  if (std::isfinite(rep.start_val)) best.val = rep.start_val;
  long longest = 0;
  for (const RowRange& r : train) longest = std::max(longest, r.end - r.begin);
  // A short data set gets windows as long as its pieces allow.
  const int H = int(std::min<long>(o.horizon, longest));
  if (H < 2) {
    rep.best_val = best.val;
    return rep;
  }

  adam_epochs(net, s, train, val, o, H, progress, best, rep);
  lbfgs(net, s, train, val, o, H, progress, best, rep);
  rep.best_val = best.val;
  return rep;
}

}  // namespace nlsoft::model
