#include "app/model/train.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>

#include <mutex>
#include <thread>

#include <Eigen/QR>

#include "app/model/adam.hpp"
#include "app/model/error.hpp"
#include "app/model/excitation.hpp"
#include "app/model/fit_scores.hpp"
#include "app/model/linear_start.hpp"
#include "app/model/pooled_runs.hpp"
#include "shared/forward.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::model {
namespace {

struct LossValue {
  double value;
  Eigen::MatrixXd grad;
};

LossValue loss_of(Loss kind, double delta, const Eigen::MatrixXd& out, const Eigen::MatrixXd& target) {
  const Eigen::ArrayXXd e = (out - target).array();
  const double count = static_cast<double>(e.size());
  if (kind == Loss::Mse) return {e.square().sum() / count, (2.0 / count) * e.matrix()};
  const Eigen::ArrayXXd a = e.abs();
  const Eigen::ArrayXXd h = (a <= delta).select(0.5 * e.square(), delta * (a - 0.5 * delta));
  const Eigen::ArrayXXd g = (a <= delta).select(e, delta * e.sign());
  return {h.sum() / count, (1.0 / count) * g.matrix()};
}

// Targets in network units for raw labels Y given the (possibly perturbed)
// residual base.
Eigen::MatrixXd targets(const Normalisation& nz, const Eigen::MatrixXd& Y, const Eigen::MatrixXd* base) {
  Eigen::MatrixXd t = Y;
  if (base) t -= *base;
  return (t.rowwise() - nz.out_offset.transpose()).array().rowwise() / nz.out_scale.transpose().array();
}

template <class L>
bool is_single_linear(const std::vector<L>& l) {
  return l.size() == 1 && l[0].kind == LayerKind::Dense && l[0].act == Activation::Linear;
}

// RMS over rows and outputs of T - [X 1] W, the products summed in float as
// the firmware sums them (float inputs, float weights), or in double.
template <class F>
double residual_rms(const Eigen::MatrixXd& X, const Eigen::MatrixXd& W, const Eigen::MatrixXd& T) {
  const Eigen::Index in = X.cols();
  double sum = 0.0;
  for (Eigen::Index r = 0; r < X.rows(); ++r)
    for (Eigen::Index j = 0; j < T.cols(); ++j) {
      F z = F(W(in, j));
      for (Eigen::Index i = 0; i < in; ++i) z += F(X(r, i)) * F(W(i, j));
      sum += (double(z) - T(r, j)) * (double(z) - T(r, j));
    }
  return std::sqrt(sum / double(std::max<Eigen::Index>(1, X.rows() * T.cols())));
}

// A single linear layer under MSE is least squares: solve it exactly
// (column-pivoting QR copes with the near-collinear y(k), y(k-1) columns
// that would take Adam forever). Where columns are all but dependent (a prbs
// run: each input at two levels, its lags and the sensors that follow it)
// the exact solution's weights reach 1e9 and cancel in double only: the
// float model the firmware runs then misses by the task space's size. So
// the least ridge (lambda |W|^2, the bias free, from none up) whose float
// sums fit the training rows as well as its double ones is kept.
void solve_linear(Network& net, const Eigen::MatrixXd& Xn, const Eigen::MatrixXd& T) {
  const Eigen::Index rows = Xn.rows(), in = Xn.cols();
  Eigen::MatrixXd A(rows, in + 1);
  A << Xn, Eigen::VectorXd::Ones(rows);
  Eigen::MatrixXd W = A.colPivHouseholderQr().solve(T);
  const double scale = std::sqrt(T.squaredNorm() / double(std::max<Eigen::Index>(1, T.size())));
  for (double lambda : {1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2}) {
    const double exact = residual_rms<double>(Xn, W, T);
    if (residual_rms<float>(Xn, W, T) <= 1.1 * exact + 1e-6 * scale) break;
    // [A; sqrt(lambda rows) I] W = [T; 0]: the normal equations plus lambda rows I.
    Eigen::MatrixXd Ar = Eigen::MatrixXd::Zero(rows + in, in + 1);
    Eigen::MatrixXd Tr = Eigen::MatrixXd::Zero(rows + in, T.cols());
    Ar.topRows(rows) = A;
    Ar.bottomLeftCorner(in, in) = std::sqrt(lambda * double(rows)) * Eigen::MatrixXd::Identity(in, in);
    Tr.topRows(rows) = T;
    W = Ar.colPivHouseholderQr().solve(Tr);
  }
  const int out = static_cast<int>(T.cols());
  double* th = net.theta().data();
  for (int i = 0; i < int(in); ++i)
    for (int j = 0; j < out; ++j) th[i * out + j] = W(i, j);
  for (int j = 0; j < out; ++j) th[in * out + j] = W(in, j);
}

// The one-step problem: normalised inputs and targets, the split.
struct OneStepData {
  const InputLayout& L;
  const Eigen::MatrixXd& Xn;
  const RowMajorMatrix& Xn_rows;  // the same, row-major: a mini-batch draws rows at random
  const Eigen::MatrixXd& T;
  const RowMajorMatrix& T_rows;  // the same, row-major: a column-major row is a cache miss per output
  const Partition& P;
  const Normalisation& nz;
};

struct OneStepResult {
  double best_val = 0;
  int epochs = 0;
};

// The training rows order[start, start + size) as a mini-batch, their
// y-history inputs perturbed by opt.y_noise.
void fill_batch(const OneStepData& d, const TrainOptions& opt, const std::vector<long>& order, long start, long size,
                Random& rng, Eigen::MatrixXd& Xb, Eigen::MatrixXd& Tb) {
  const InputLayout& L = d.L;
  Xb.resize(size, L.p());
  Tb.resize(size, L.n);
  for (long b = 0; b < size; ++b) {
    const long r = order[size_t(start + b)];
    Xb.row(b) = d.Xn_rows.row(r);
    Tb.row(b) = d.T_rows.row(r);
  }
  if (!(opt.y_noise > 0.0)) return;
  // Independent errors per lag: a shared drift alone would leave
  // y(k) - y(k-1) clean, and the network would learn to integrate
  // that difference, which runs away once it is fed its own output.
  for (long b = 0; b < size; ++b) {
    for (int lag = 0; lag < L.dd; ++lag) {
      for (int j = 0; j < L.n; ++j) {
        const int col = L.y_begin() + lag * L.n + j;
        const double dn = opt.y_noise * rng.gaussian();
        Xb(b, col) += dn;
        if (opt.residual && lag == 0) Tb(b, j) -= dn / d.nz.in_scale(col) / d.nz.out_scale(j);
      }
    }
  }
}

// One pass of Adam over the training rows, shuffled; the mean batch loss.
double adam_epoch(Network& net, const OneStepData& d, const TrainOptions& opt, std::vector<long>& order, Random& rng,
                  Adam& adam, double lr) {
  const long ntrain = d.P.train_end;
  for (long i = ntrain - 1; i > 0; --i)  // Fisher-Yates, portable
    std::swap(order[size_t(i)], order[size_t(rng.integer(0, i))]);
  Network::Cache cache;
  Eigen::MatrixXd Xb, Tb;
  std::vector<double> grad;
  double sum = 0.0;
  long batches = 0;
  for (long start = 0; start < ntrain; start += opt.batch) {
    fill_batch(d, opt, order, start, std::min<long>(opt.batch, ntrain - start), rng, Xb, Tb);
    const Eigen::MatrixXd& out = net.forward(Xb, cache);
    const LossValue lv = loss_of(opt.loss, opt.huber_delta, out, Tb);
    net.backward(cache, lv.grad, grad);
    adam.step(net.theta(), grad, lr);
    sum += lv.value;
    ++batches;
  }
  return sum / static_cast<double>(std::max(1L, batches));
}

// The paper's training, and the simulation objective's warm start: least
// squares for a single linear layer, else Adam on shuffled mini-batches of
// rows with early stopping on the validation rows' one-step loss.
OneStepResult warm_start(Network& net, const OneStepData& d, const TrainOptions& opt, Random& rng,
                         const std::function<void(const Progress&)>& progress) {
  const Partition& P = d.P;
  const long ntrain = P.train_end;
  const Eigen::MatrixXd Xval = d.Xn.middleRows(P.val_begin, P.val_end - P.val_begin);
  const Eigen::MatrixXd Tval = d.T.middleRows(P.val_begin, P.val_end - P.val_begin);
  auto val_loss = [&]() { return loss_of(Loss::Mse, 1.0, net.predict(Xval), Tval).value; };
  OneStepResult res;
  if (is_single_linear(net.layers()) && opt.loss == Loss::Mse &&
      (opt.y_noise == 0.0 || opt.objective == Objective::Simulation)) {
    solve_linear(net, d.Xn.topRows(ntrain), d.T.topRows(ntrain));
    res.best_val = val_loss();
    Progress p;
    p.epochs = 0;
    p.val_loss = p.best_val = res.best_val;
    progress(p);
    return res;
  }
  std::vector<double>& th = net.theta();
  std::vector<double> best = th;
  std::vector<long> order(static_cast<size_t>(ntrain));
  std::iota(order.begin(), order.end(), 0L);
  Adam adam(th.size());
  double lr = opt.lr;
  double best_val = val_loss();
  int since_best = 0, since_cut = 0;
  const int cut_after = std::max(3, opt.patience / 3);
  for (int epoch = 1; epoch <= opt.epochs; ++epoch) {
    if (opt.stop && opt.stop->load(std::memory_order_relaxed)) break;
    const double train_loss = adam_epoch(net, d, opt, order, rng, adam, lr);
    const double v = val_loss();
    if (!std::isfinite(v)) throw PipelineError("training diverged (validation loss not finite); try a smaller --lr");
    ++since_cut;
    if (v < best_val) {
      best_val = v;
      best = th;
      since_best = 0;
    } else {
      ++since_best;
    }
    // Halve the rate on a plateau: the last digits of accuracy need small steps.
    if (since_best >= cut_after && since_cut >= cut_after) {
      lr *= 0.5;
      since_cut = 0;
    }
    res.epochs = epoch;
    Progress p;
    p.epoch = epoch;
    p.epochs = opt.epochs;
    p.train_loss = train_loss;
    p.val_loss = v;
    p.best_val = best_val;
    p.lr = lr;
    progress(p);
    if (since_best >= opt.patience) break;
  }
  th = best;
  res.best_val = best_val;
  return res;
}

// fit_simulation's reports as train's progress: the phase, the step and
// the losses.
SimulationProgress as_progress(const std::function<void(const Progress&)>& to) {
  return [to](const char* phase, int step, int steps, double loss, double val, double best) {
    Progress p;
    p.phase = phase;
    p.epoch = step;
    p.epochs = steps;
    p.train_loss = loss;
    p.val_loss = val;
    p.best_val = best;
    to(p);
  };
}

// The recursion's view of the data: each output weighted by the inverse of
// its variance over the training rows, so outputs of different units count
// alike.
SimulationData simulation_data(const Dataset& d, const Eigen::MatrixXd& Xn, const Normalisation& nz,
                               const InputLayout& L, long train_rows, bool residual) {
  SimulationData s;
  s.layout = L;
  s.Xn = Xn;
  s.Y = d.Y;
  s.y_in_offset = nz.in_offset.segment(L.y_begin(), L.n);
  s.y_in_scale = nz.in_scale.segment(L.y_begin(), L.n);
  s.out_offset = nz.out_offset;
  s.out_scale = nz.out_scale;
  s.residual = residual;
  s.weight.resize(L.n);
  const Eigen::MatrixXd Yt = d.Y.topRows(train_rows);
  for (int j = 0; j < L.n; ++j) {
    const double mean = Yt.col(j).mean();
    const double var = (Yt.col(j).array() - mean).square().mean();
    s.weight(j) = var > 0.0 ? 1.0 / var : 1.0;
  }
  return s;
}

// A model's free run of `pieces` (from each piece's measured start), as
// the firmware runs it: MSE / variance summed over outputs (what chooses),
// and RMSE per output (what the held-out table prints).
struct HeldOutScore {
  double loss = 0;
  std::vector<double> rmse;
};
HeldOutScore held_out_score(const ModelFile& model, const Dataset& d, const std::vector<RowRange>& pieces,
                            const Eigen::VectorXd& inverse_variance) {
  const Simulation sim = simulate_network(model, d, pieces);
  const Eigen::MatrixXd y = measured(d, pieces);
  HeldOutScore h;
  const double rows = double(std::max<Eigen::Index>(1, y.rows()));
  for (Eigen::Index j = 0; j < y.cols(); ++j) {
    const double mse = (sim.free_run.col(j) - y.col(j)).squaredNorm() / rows;
    // A model whose free run leaves the float range is the worst, not NaN.
    h.loss += std::isfinite(mse) ? mse * inverse_variance(j) : HUGE_VAL;
    h.rmse.push_back(std::sqrt(mse));
  }
  return h;
}

}  // namespace

bool Candidate::is_network() const { return !is_single_linear(layers); }

Eigen::MatrixXd TrainedNetwork::predict(const Eigen::MatrixXd& X_raw) const {
  const Eigen::MatrixXd out = net.predict(normalise_inputs(nz, X_raw));
  Eigen::MatrixXd y = (out.array().rowwise() * nz.out_scale.transpose().array()).matrix().rowwise() +
                      nz.out_offset.transpose();
  if (residual) y += X_raw.middleCols(layout.y_begin(), layout.n);
  return y;
}

ModelFile TrainedNetwork::export_model(uint8_t platform) const {
  ModelFile f;
  Model<HostCapacity>& M = f.shape;
  M.m = uint8_t(layout.m);
  M.n = uint8_t(layout.n);
  M.w = uint8_t(layout.w);
  M.nd = uint8_t(layout.nd);
  M.dd = uint8_t(layout.dd);
  M.residual = residual;
  if (net.layers().size() > size_t(HostCapacity::layers)) throw PipelineError("too many layers");
  M.layer_count = uint8_t(net.layers().size());
  for (size_t i = 0; i < net.layers().size(); ++i) M.layer[i] = net.layers()[i];
  auto put = [&](const Eigen::VectorXd& v) {
    for (Eigen::Index i = 0; i < v.size(); ++i) f.params.push_back(static_cast<float>(v(i)));
  };
  put(nz.in_offset);
  put(nz.in_scale);
  put(nz.out_offset);
  put(nz.out_scale);
  for (double t : net.theta()) f.params.push_back(static_cast<float>(t));
  f.platform = platform;
  finalize(f);
  return f;
}

Evaluation evaluate(const ModelFile& model, const Dataset& d, long begin, long end) {
  return evaluate(model, d, std::vector<RowRange>{{begin, end}});
}

Evaluation evaluate(const ModelFile& model, const Dataset& d, const std::vector<RowRange>& pieces) {
  const Model<HostCapacity> M = model.view();
  const InputLayout& L = d.layout;
  if (M.p() != L.p() || M.n != L.n || M.nd != L.nd || M.dd != L.dd)
    throw PipelineError("the model's dimensions do not match the data");
  Evaluation ev;
  ev.mse.assign(size_t(L.n), 0.0);
  ev.free_run_mse.assign(size_t(L.n), 0.0);
  ForwardScratch<HostCapacity, float> scratch;
  float x[Dims<HostCapacity>::p], y[HostCapacity::n];
  float yq[HostCapacity::nd * HostCapacity::n];  // own predictions, newest first
  for (const RowRange& piece : pieces) {
    const long begin = piece.begin, end = piece.end;
    if (end <= begin) continue;
    for (int i = 0; i < L.dd * L.n; ++i) yq[i] = static_cast<float>(d.X(begin, L.y_begin() + i));
    for (long r = begin; r < end; ++r) {
      for (int i = 0; i < L.p(); ++i) x[i] = static_cast<float>(d.X(r, i));
      forward(M, x, y, scratch);
      for (int j = 0; j < L.n; ++j) ev.mse[size_t(j)] += (double(y[j]) - d.Y(r, j)) * (double(y[j]) - d.Y(r, j));
      for (int i = 0; i < L.dd * L.n; ++i) x[L.y_begin() + i] = yq[i];
      forward(M, x, y, scratch);
      for (int j = 0; j < L.n; ++j) ev.free_run_mse[size_t(j)] += (double(y[j]) - d.Y(r, j)) * (double(y[j]) - d.Y(r, j));
      for (int i = L.dd * L.n - 1; i >= L.n; --i) yq[i] = yq[i - L.n];
      for (int j = 0; j < L.n; ++j) yq[j] = y[j];
    }
    ev.rows += end - begin;
  }
  if (ev.rows == 0) return ev;
  const double count = static_cast<double>(ev.rows);
  for (int j = 0; j < L.n; ++j) {
    ev.mse[size_t(j)] /= count;
    ev.free_run_mse[size_t(j)] /= count;
  }
  return ev;
}


void check_dimensions(const Series& s, const PlantTarget& target) {
  if (s.m != target.m || s.n != target.n || s.w != target.w)
    throw PipelineError((s.name.empty() ? std::string("the data") : s.name) + " has m=" + std::to_string(s.m) +
                        " n=" + std::to_string(s.n) + " w=" + std::to_string(s.w) + " but rig '" + target.name +
                        "' has m=" + std::to_string(target.m) + " n=" + std::to_string(target.n) +
                        " w=" + std::to_string(target.w));
}

namespace {

using Clock = std::chrono::steady_clock;

// What cannot be trained, refused before any data is pooled.
void check_request(const std::vector<Series>& runs, const PlantTarget& target, const TrainOptions& opt, int validate) {
  if (runs.empty()) throw PipelineError("no data to train on");
  if (validate >= int(runs.size())) throw PipelineError("the validation run is not among the runs");
  if (validate >= 0 && runs.size() < 2) throw PipelineError("a validation run needs at least one other run to train on");
  for (const Series& s : runs) check_dimensions(s, target);
  const Series& s = runs.front();
  if (opt.layers.empty() || opt.layers.back().units != s.n)
    throw PipelineError("the last layer must have n = " + std::to_string(s.n) + " units");
  if (opt.epochs < 1 || opt.batch < 1 || !(opt.lr > 0.0) || !(opt.y_noise >= 0.0) || !(opt.huber_delta > 0.0))
    throw PipelineError("epochs, batch, lr and huber delta must be positive, y noise non-negative");
  if (opt.folds < 2) throw PipelineError("a time-series split needs at least 2 folds");
}

NormalisationSpec normalisation_spec(const PlantTarget& target, const TrainOptions& opt, int m) {
  NormalisationSpec spec;
  // The limits as the controller holds them (float), as the rig file gives them.
  for (int i = 0; i < m; ++i) {
    spec.u_lo.push_back(double(float(target.u_lo[size_t(i)])));
    spec.u_hi.push_back(double(float(target.u_hi[size_t(i)])));
  }
  // Outputs centred on the rig's rest (its file's `rest`, by default the
  // middle of each output's range), as the controller holds it (float): a
  // property of the rig, not of a simulated plant that may not be the rig.
  for (double y : target.y_rest) spec.y_neutral.push_back(double(float(y)));
  spec.residual = opt.residual;
  const Activation out_act = opt.layers.back().act;
  spec.out_margin = (out_act == Activation::Linear || out_act == Activation::Relu) ? 1.0 : 1.25;
  return spec;
}

// The candidates: every size, every seed.
std::vector<Candidate> candidate_list(const TrainOptions& opt, int n) {
  std::vector<std::vector<LayerSpec>> sizes{opt.layers};
  for (const auto& a : opt.alternatives) {
    if (a.empty() || a.back().units != n)
      throw PipelineError("the last layer must have n = " + std::to_string(n) + " units");
    sizes.push_back(a);
  }
  // The linear output-error model is always among the candidates: a
  // network is kept only where it simulates the held-out rows better.
  if (opt.objective == Objective::Simulation &&
      std::none_of(sizes.begin(), sizes.end(), [](const std::vector<LayerSpec>& l) { return is_single_linear(l); }))
    sizes.push_back({{LayerKind::Dense, n, Activation::Linear}});
  std::vector<Candidate> out;
  for (const auto& size : sizes) {
    // A single linear layer starts from least squares, whatever the seed.
    for (int k = 0; k < (is_single_linear(size) ? 1 : std::max(1, opt.seeds)); ++k) {
      Candidate c;
      c.layers = size;
      c.seed = opt.seed + uint64_t(k);
      out.push_back(c);
    }
  }
  return out;
}

// fit(i, inner_threads) for every i < count, on opt_threads threads at once;
// alone, one candidate spreads its full-batch passes over them instead. The
// first exception is rethrown once every thread is done.
void for_each_candidate(size_t count, int opt_threads, const std::function<void(size_t, int)>& fit) {
  const int threads = std::max(1, std::min(opt_threads, int(count)));
  if (threads == 1) {
    for (size_t i = 0; i < count; ++i) fit(i, opt_threads);
    return;
  }
  std::atomic<size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&] {
      for (size_t i; (i = next.fetch_add(1)) < count;) {
        try {
          fit(i, 1);
        } catch (...) {
          std::lock_guard<std::mutex> lock(failure_mutex);
          if (!failure) failure = std::current_exception();
        }
      }
    });
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

// One call of train(): the pooled data in the forms each step reads, and
// each candidate's network and one-step score beside res.candidates (the
// same index).
class Training {
 public:
  Training(const PlantTarget& target, const TrainOptions& opt) : target_(target), opt_(opt), t0_(Clock::now()) {}
  Training(const Training&) = delete;
  Training& operator=(const Training&) = delete;

  TrainResult run(const std::vector<Series>& runs, int validate);

 private:
  const Dataset& d() const { return pooled_.d; }
  const InputLayout& layout() const { return pooled_.d.layout; }
  const Partition& split() const { return res_.split; }
  double elapsed_s() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }
  void prepare(const std::vector<Series>& runs, int validate);
  void fit_linear_start();
  void fit_candidate(size_t i, int inner_threads);
  void add_candidate(const Candidate& c, const Network& net);
  HeldOutScore held_out(const Network& net) const;
  void choose();
  void keep_rig_shape();
  void finish(int validate);

  const PlantTarget& target_;
  const TrainOptions& opt_;
  const Clock::time_point t0_;
  int n_ = 0;
  TrainResult res_;
  Pooled pooled_;
  Eigen::MatrixXd Xn_, T_, Xval_, Tval_;  // normalised inputs, targets; their validation rows
  RowMajorMatrix T_rows_;                  // T_ row-major, for the mini-batches
  SimulationData sim_;
  std::vector<RowRange> train_pieces_, judge_pieces_;
  Network start_model_;  // the linear model networks may start from
  std::vector<Network> nets_;
  // The single linear layer's least-squares start is ARX on these lags (in
  // normalised units, with the ridge float needs): a candidate of its own.
  Network least_squares_;
  std::vector<double> one_step_val_;
  std::vector<int> one_step_epochs_;
  std::mutex progress_mutex_;
};

// The runs pooled and split, the normalisation fitted on the training rows,
// and the rows in network units.
void Training::prepare(const std::vector<Series>& runs, int validate) {
  n_ = runs.front().n;
  pooled_ = pool_runs(runs, opt_.nd, opt_.dd, opt_.folds, validate);
  res_.split = pooled_.split;
  res_.held_out = pooled_.held_out;
  const Partition& P = split();
  if (P.train_end < 1 || P.val_end <= P.val_begin || P.test_end <= P.test_begin)
    throw PipelineError("too few rows to train, validate and test");
  TrainedNetwork& tn = res_.trained;
  tn.layout = layout();
  tn.residual = opt_.residual;
  tn.nz = fit_normalisation(d(), P.train_end, normalisation_spec(target_, opt_, runs.front().m));
  const InputLayout& L = layout();
  Xn_ = normalise_inputs(tn.nz, d().X);
  const Eigen::MatrixXd base = d().X.middleCols(L.y_begin(), L.n);
  T_ = targets(tn.nz, d().Y, opt_.residual ? &base : nullptr);
  T_rows_ = T_;
  sim_ = simulation_data(d(), Xn_, tn.nz, L, P.train_end, opt_.residual);
  train_pieces_ = pieces_within(d(), 0, P.train_end);
  // Candidates and their weights are judged by free runs of the training
  // and the validation rows, each stretch from its measured start. Windows
  // train a model H steps at a time; drift over a long run shows only in a
  // long run, and the validation rows of a small data set are too few to
  // show it (cascaded tanks: 92 rows; the network they chose simulated the
  // test set at 3.7 V, the one the long runs choose at 0.67 V).
  judge_pieces_ = pieces_within(d(), 0, P.val_end);
}

// The linear model the networks start from, fitted once before the
// candidates (the same for every seed), as a linear candidate is trained:
// least squares, then the simulation objective.
void Training::fit_linear_start() {
  if (opt_.objective == Objective::Simulation && opt_.start == Start::Linear) {
    for (Candidate& c : res_.candidates) c.linear_start = !is_single_linear(c.layers) && holds_linear_model(c.layers, n_);
  }
  if (std::none_of(res_.candidates.begin(), res_.candidates.end(), [](const Candidate& c) { return c.linear_start; }))
    return;
  start_model_ = Network(layout().p(), {{LayerKind::Dense, n_, Activation::Linear}});
  Random rng(opt_.seed);
  start_model_.initialise(rng);
  auto progress = [&](const Progress& p) {
    if (!opt_.progress) return;
    Progress q = p;
    q.candidate = -1;
    q.elapsed_s = elapsed_s();
    opt_.progress(q);
  };
  warm_start(start_model_, OneStepData{layout(), Xn_, sim_.Xn, T_, T_rows_, split(), res_.trained.nz}, opt_, rng, progress);
  SimulationOptions so = opt_.sim;
  so.seed = opt_.seed;
  so.stop = opt_.stop;
  so.threads = opt_.threads;
  fit_simulation(start_model_, sim_, train_pieces_, judge_pieces_, so, as_progress(progress));
}

void Training::fit_candidate(size_t i, int inner_threads) {
  auto report = [&](Progress p) {
    if (!opt_.progress) return;
    p.candidate = int(i);
    p.candidates = int(res_.candidates.size());
    p.elapsed_s = elapsed_s();
    std::lock_guard<std::mutex> lock(progress_mutex_);
    opt_.progress(p);
  };
  Candidate& c = res_.candidates[i];
  Network& net = nets_[i];
  net = Network(layout().p(), c.layers);
  Random rng(c.seed);
  net.initialise(rng);
  c.weights = net.param_count();
  if (c.linear_start) {
    embed_linear_model(net, start_model_, Xn_.topRows(split().train_end));
    one_step_val_[i] = loss_of(Loss::Mse, 1.0, net.predict(Xval_), Tval_).value;
  } else {
    const OneStepResult w =
        warm_start(net, OneStepData{layout(), Xn_, sim_.Xn, T_, T_rows_, split(), res_.trained.nz}, opt_, rng, report);
    one_step_val_[i] = w.best_val;
    one_step_epochs_[i] = w.epochs;
    c.one_step_epochs = w.epochs;
    if (is_single_linear(c.layers)) least_squares_ = net;  // one such candidate: one writer
  }
  c.warm_free_run = free_run_loss(net, sim_, judge_pieces_);
  c.val_free_run = c.warm_free_run;
  if (opt_.objective == Objective::Simulation) {
    SimulationOptions so = opt_.sim;
    so.seed = c.seed;
    so.stop = opt_.stop;
    so.threads = inner_threads;
    const SimulationReport r = fit_simulation(net, sim_, train_pieces_, judge_pieces_, so, as_progress(report));
    c.val_free_run = r.best_val;
    c.epochs = r.epochs;
    c.evals = r.evals;
  }
}

// A candidate made after the others were fitted (least squares, the rig
// shape's carrier): no epochs of its own.
void Training::add_candidate(const Candidate& c, const Network& net) {
  res_.candidates.push_back(c);
  nets_.push_back(net);
  one_step_val_.push_back(loss_of(Loss::Mse, 1.0, net.predict(Xval_), Tval_).value);
  one_step_epochs_.push_back(0);
}

// Judged where none was fitted or stopped: the held-out rows' free run, run
// as the firmware runs the model file (the held-out table's figures).
HeldOutScore Training::held_out(const Network& net) const {
  TrainedNetwork t = res_.trained;
  t.net = net;
  return held_out_score(t.export_model(target_.platform), d(), pooled_.test_pieces, sim_.weight);
}

// Kept: the best held-out free run (simulation), or the best one-step
// validation loss (one-step); on a tie the one with fewer weights.
void Training::choose() {
  const bool simulation = opt_.objective == Objective::Simulation;
  for (size_t i = 1; i < res_.candidates.size(); ++i) {
    const Candidate &c = res_.candidates[i], &k = res_.candidates[res_.chosen];
    const double ci = simulation ? c.held_out : one_step_val_[i];
    const double ki = simulation ? k.held_out : one_step_val_[res_.chosen];
    if (ci < ki || (ci == ki && c.weights < k.weights)) res_.chosen = i;
  }
  if (simulation && !res_.candidates[res_.chosen].is_network()) {
    for (size_t i = 0; i < res_.candidates.size(); ++i)
      if (res_.candidates[i].is_network() &&
          (res_.beaten_network == size_t(-1) ||
           res_.candidates[i].held_out < res_.candidates[res_.beaten_network].held_out))
        res_.beaten_network = i;
  }
}

// A rig whose images are built for its [model] shape gets a model of that
// shape: the winning linear model carried in it, to the last bit of double
// rounding, or, where the shape cannot carry it (a GRU, a tanh output), the
// best network of the shape, and train says by how much it lost.
void Training::keep_rig_shape() {
  if (!(opt_.objective == Objective::Simulation && opt_.keep_shape && res_.beaten_network != size_t(-1) &&
        !is_single_linear(opt_.layers)))
    return;
  const size_t linear = res_.chosen;
  if (!holds_linear_model(opt_.layers, n_)) {
    res_.linear_not_carried = linear;
    res_.chosen = res_.beaten_network;
    res_.beaten_network = size_t(-1);
    return;
  }
  Network carrier(layout().p(), opt_.layers);
  Random rng(opt_.seed);
  carrier.initialise(rng);
  embed_linear_model(carrier, nets_[linear], Xn_.topRows(split().train_end));
  Candidate c;
  c.layers = opt_.layers;
  c.seed = opt_.seed;
  c.linear_start = true;
  c.weights = carrier.param_count();
  c.val_free_run = c.warm_free_run = free_run_loss(carrier, sim_, judge_pieces_);
  const HeldOutScore h = held_out(carrier);
  c.held_out = h.loss;
  c.held_out_rmse = h.rmse;
  add_candidate(c, carrier);
  res_.carried_linear = linear;
  res_.chosen = res_.candidates.size() - 1;
}

// The chosen network exported, scored on the test rows beside the ARX
// baseline, and the data handed over.
void Training::finish(int validate) {
  const Partition& P = split();
  TrainedNetwork& tn = res_.trained;
  tn.net = std::move(nets_[res_.chosen]);
  res_.best_val_loss = one_step_val_[res_.chosen];
  res_.epochs_run = one_step_epochs_[res_.chosen];
  res_.objective = opt_.objective;
  res_.stopped = opt_.stop && opt_.stop->load();
  // The model file names a shipped rig by its INFO number, or none (255).
  res_.model = tn.export_model(target_.platform);
  res_.test = evaluate(res_.model, d(), pooled_.test_pieces);
  // The baseline beside it; a training part too short for its
  // coefficients leaves none (theta empty) rather than refuse the model.
  try {
    res_.arx = fit_arx(d(), pieces_within(d(), 0, P.train_end));
  } catch (const PipelineError&) {
    res_.arx = ArxModel{};
  }
  res_.val_pieces = pieces_within(d(), P.val_begin, P.val_end);
  res_.test_pieces = pooled_.test_pieces;
  res_.validate_run = validate >= 0;
  res_.folds = opt_.folds;
  res_.data = std::move(pooled_.d);
  res_.seconds = elapsed_s();
}

TrainResult Training::run(const std::vector<Series>& runs, int validate) {
  check_request(runs, target_, opt_, validate);
  prepare(runs, validate);
  res_.candidates = candidate_list(opt_, n_);
  fit_linear_start();
  const Partition& P = split();
  Xval_ = Xn_.middleRows(P.val_begin, P.val_end - P.val_begin);
  Tval_ = T_.middleRows(P.val_begin, P.val_end - P.val_begin);
  nets_.resize(res_.candidates.size());
  one_step_val_.assign(res_.candidates.size(), 0.0);
  one_step_epochs_.assign(res_.candidates.size(), 0);
  // Each candidate's result does not depend on which thread trained it.
  for_each_candidate(res_.candidates.size(), opt_.threads,
                     [this](size_t i, int inner_threads) { fit_candidate(i, inner_threads); });
  if (opt_.objective == Objective::Simulation && !least_squares_.layers().empty()) {
    Candidate a;
    a.layers = {{LayerKind::Dense, n_, Activation::Linear}};
    a.seed = opt_.seed;
    a.arx = true;
    a.weights = least_squares_.param_count();
    a.val_free_run = a.warm_free_run = free_run_loss(least_squares_, sim_, judge_pieces_);
    add_candidate(a, least_squares_);
  }
  if (opt_.objective == Objective::Simulation) {
    for (size_t i = 0; i < res_.candidates.size(); ++i) {
      const HeldOutScore h = held_out(nets_[i]);
      res_.candidates[i].held_out = h.loss;
      res_.candidates[i].held_out_rmse = h.rmse;
    }
  }
  choose();
  keep_rig_shape();
  finish(validate);
  return std::move(res_);
}

}  // namespace

TrainResult train(const Series& s, const PlantTarget& target, const TrainOptions& opt) {
  return train(std::vector<Series>{s}, target, opt);
}

TrainResult train(const std::vector<Series>& runs, const PlantTarget& target, const TrainOptions& opt, int validate) {
  return Training(target, opt).run(runs, validate);
}

TrainOptions default_options(const PlantTarget& target, Objective objective) {
  // The rig's [model] layers, or a small relu network: residual
  // (y(k+1) - y(k)) when its controller feeds back measured outputs. Trained for simulation, no rig needs the
  // y-history noise the one-step objective relies on to make a model that
  // survives its own predictions (an absolute model trained one step on
  // noiseless measured histories tracked a 20 mm-span rig at 1.2 mm RMSE).
  TrainOptions o;
  o.objective = objective;
  // Two widths of relu, the wider one a candidate beside the narrower: on the
  // measured benchmarks (README, "On real data") relu simulated the test sets
  // 1.5-3x better than tanh of the same width, and validation picks the width
  // (16 on the 1 000-sample tanks, 32 on the Silverbox and Wiener-Hammerstein).
  o.layers = {{LayerKind::Dense, 16, Activation::Relu}, {LayerKind::Dense, target.n, Activation::Tanh}};
  o.residual = target.measured_feedback;
  o.y_noise = target.measured_feedback ? 0.0 : 0.05;
  // With no shape in the rig file, a single linear layer (the output-error
  // model) is a candidate too: where the network does not simulate the
  // validation rows better, the rig gets the linear model, which
  // contains ARX's.
  if (target.layers.empty() && objective == Objective::Simulation) {
    o.alternatives.push_back({{LayerKind::Dense, 32, Activation::Relu}, {LayerKind::Dense, target.n, Activation::Tanh}});
    o.alternatives.push_back({{LayerKind::Dense, target.n, Activation::Linear}});
  }
  if (!target.layers.empty()) o.layers = target.layers;
  o.keep_shape = !target.layers.empty();
  o.nd = target.nd;
  o.dd = target.dd;
  o.sim.horizon = std::max(target.horizon, o.sim.horizon);
  // Four networks in all, two at a time on two cores: two seeds of each
  // width, or four of the rig's one shape. A small network's free run lands
  // in minima far apart from one seed to the next (tendon's GRU(5) from
  // 10 minutes of prbs: 5.2 to 41 % nRMSE over five ident seeds with two
  // seeds each; 4.2 to 5.8 % with four), and the validation free run picks
  // among them.
  o.seeds = objective != Objective::Simulation ? 1 : (target.layers.empty() ? 2 : 4);
  return o;
}


std::string describe_layers(const std::vector<LayerSpec>& layers) {
  std::string out;
  for (const LayerSpec& l : layers) {
    if (!out.empty()) out += ", ";
    out += std::string(layer_kind_info(l.kind).title) + " " + std::to_string(l.units);
    if (layer_kind_info(l.kind).free_activation) out += std::string(" ") + activation_name(l.act);
  }
  return out;
}

}  // namespace nlsoft::model
