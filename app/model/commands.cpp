#include "app/model/commands.hpp"

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/model/atomic_file.hpp"
#include "app/model/csv.hpp"
#include "app/model/error.hpp"
#include "app/model/excitation.hpp"
#include "app/model/input_levels.hpp"
#include "app/model/keras_import.hpp"
#include "app/model/lag_search.hpp"
#include "app/model/model_fit.hpp"
#include "app/model/model_size_words.hpp"
#include "app/model/plant_model.hpp"
#include "app/model/progress.hpp"
#include "app/model/train.hpp"
#include "host/rig/rig_option.hpp"
#include "shared/forward.hpp"

namespace nlsoft::console {

using host::add_rig_option;

namespace {

using namespace nlsoft::model;

// Numbers arrive as strings so every malformed value gets our message and
// exit code 2 rather than a parser-specific code.
long to_long(const std::string& opt, const std::string& s, long lo, long hi) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || errno == ERANGE || v < lo || v > hi)
    throw PipelineError(opt + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                        "], got '" + s + "'");
  return v;
}

double to_double(const std::string& opt, const std::string& s, double lo, double hi) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
    throw PipelineError(opt + " must be a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" +
                        s + "'");
  return v;
}


void need(const std::string& value, const std::string& opt) {
  if (value.empty()) throw PipelineError(opt + " is required (see --help)");
}

std::vector<int> to_units(const std::string& s) {
  std::vector<int> units;
  if (s == "none" || s == "0") return units;
  std::stringstream ss(s);
  std::string part;
  while (std::getline(ss, part, ',')) units.push_back(static_cast<int>(to_long("--hidden", part, 1, 48)));
  if (units.empty()) throw PipelineError("--hidden needs a list like 5,5 (or 'none')");
  return units;
}

// ---------------------------------------------------------------- dataset
struct DatasetArgs {
  std::string rig, out, steps, seed = "1";
};

void run_dataset(const DatasetArgs& a, const TargetResolver& resolve) {
  need(a.rig, "--rig");
  need(a.out, "--out");
  const PlantTarget target = resolve(a.rig);
  const long steps = a.steps.empty() ? default_steps(target) : to_long("--steps", a.steps, 100, 20000000);
  const uint32_t seed = static_cast<uint32_t>(to_long("--seed", a.seed, 0, 0xffffffffL));
  const Series s = generate_excitation(target, steps, seed);
  write_series_csv(a.out, s);
  std::printf("wrote %s: %ld samples of %s (m=%d n=%d w=%d, %.1f s at %.0f Hz), seed %u\n", a.out.c_str(), s.rows(),
              target.name.c_str(), s.m, s.n, s.w, s.time(s.rows() - 1) + (s.time(1) - s.time(0)),
              1.0 / (s.time(1) - s.time(0)), seed);
}

// ---------------------------------------------------------------- train
struct TrainArgs {
  std::string rig, out, arch, hidden, epochs, batch, lr, loss, seed, patience, y_noise, nd, dd, db;
  std::string objective, horizon, seeds, sim_epochs, lbfgs, activation, start;
  std::vector<std::string> data;
  std::vector<int64_t> runs;
  int64_t validate_run = 0;
  bool residual = false, absolute = false, plant = false;
};

// The training runs: every --data file, then every --run, then the
// --validate-run (its index returned in `validate`, else -1).
std::vector<Series> training_runs(const TrainArgs& a, const PlantTarget& target, const RunLoader& load_run,
                                  int* validate) {
  std::vector<Series> runs;
  for (const std::string& file : a.data) runs.push_back(read_training_csv(file, target));
  std::vector<int64_t> ids = a.runs;
  *validate = -1;
  if (a.validate_run > 0) {
    for (int64_t id : a.runs)
      if (id == a.validate_run)
        throw PipelineError("run " + std::to_string(id) + " is both a --run and the --validate-run: a run held out "
                            "is not trained on");
    ids.push_back(a.validate_run);
  }
  if (!ids.empty() && !load_run) throw PipelineError("--run needs the console's database, which this build lacks");
  for (size_t i = 0; i < ids.size(); ++i) {
    for (size_t j = 0; j < i; ++j)
      if (ids[j] == ids[i]) throw PipelineError("run " + std::to_string(ids[i]) + " is given twice");
    const RecordedRun r = load_run(a.db, ids[i]);
    runs.push_back(recorded_series(r, target));
    if (r.rate_hz > 0 && target.rate_hz > 0 && std::abs(r.rate_hz / target.rate_hz - 1.0) > 0.01)
      std::fprintf(stderr,
                   "nlsoft-console: warning: %s ran at %g Hz, rig '%s' at %g Hz: the model steps at the run's rate\n",
                   r.name.c_str(), r.rate_hz, target.name.c_str(), target.rate_hz);
    if (a.validate_run > 0 && ids[i] == a.validate_run) *validate = int(runs.size()) - 1;
  }
  return runs;
}

// SIGINT sets a flag while it lives, then goes back to the default action
// (so the second Ctrl-C of an impatient user still ends the process).
class InterruptGuard {
 public:
  InterruptGuard() {
    raised().store(false);
    previous_ = std::signal(SIGINT, [](int) {
      raised().store(true);
      std::signal(SIGINT, SIG_DFL);
    });
  }
  ~InterruptGuard() { std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_); }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  const std::atomic<bool>& flag() const { return raised(); }

 private:
  static std::atomic<bool>& raised() {
    static std::atomic<bool> f{false};
    return f;
  }
  void (*previous_)(int) = SIG_DFL;
};

// What train chose and why: every candidate's free run of the held-out
// rows (the rows of the held-out table printed after it), and, when a
// linear model beat every network, one line saying so with both figures.
void print_choice(const TrainResult& r, const std::string& unit) {
  if (r.stopped) std::printf("stopped (Ctrl-C): keeping the best model so far\n");
  if (r.objective == Objective::OneStep) {
    std::printf("objective one-step (the paper's): the one-step validation loss chose the weights\n");
    return;
  }
  std::printf("objective simulation: kept the candidate whose free run of the held-out rows (%s), which none was "
              "fitted on, was best (MSE / variance); each one's training stopped on its free runs of the training "
              "and validation rows\n",
              r.held_out.c_str());
  const std::string u = unit.empty() ? "" : " " + unit;
  auto rmse = [&](const Candidate& c) {
    std::string out;
    // A free run that blew up has no error to print, only the fact.
    for (double v : c.held_out_rmse)
      out += (out.empty() ? "" : ", ") + (std::isfinite(v) ? fmt::format("{:.4g}{}", v, u) : std::string("diverged"));
    return out;
  };
  for (size_t i = 0; i < r.candidates.size(); ++i) {
    const Candidate& c = r.candidates[i];
    const std::string what = c.arx ? "ARX (least squares, same lags)" : describe_layers(c.layers);
    const std::string how =
        c.arx ? "one-step least squares"
              : fmt::format("{} {:.4e}{}, {}{} L-BFGS evaluations",
                            c.linear_start               ? "started from the linear model's"
                            : c.one_step_epochs == 0     ? "least-squares start"
                                                         : "one-step warm start",
                            c.warm_free_run,
                            c.one_step_epochs > 0 ? fmt::format(" after {} one-step epochs", c.one_step_epochs) : "",
                            c.epochs > 0 ? fmt::format("{} simulation epochs, ", c.epochs) : "", c.evals);
    std::printf("  %s %-30s seed %-3llu %5zu weights  held-out free run %.4e (RMSE %s); training rows %.4e (%s)\n",
                i == r.chosen ? "*" : " ", what.c_str(), static_cast<unsigned long long>(c.seed), c.weights, c.held_out,
                rmse(c).c_str(), c.val_free_run, how.c_str());
  }
  if (r.beaten_network != size_t(-1)) {
    const Candidate& k = r.candidates[r.carried_linear != size_t(-1) ? r.carried_linear : r.chosen];
    const Candidate& n = r.candidates[r.beaten_network];
    std::printf("kept the linear model (%s): its held-out free run RMSE %s beats the best network's %s (%s)%s\n",
                k.arx ? "ARX" : "output-error", rmse(k).c_str(), rmse(n).c_str(), describe_layers(n.layers).c_str(),
                r.carried_linear != size_t(-1) ? ", carried in the rig's [model] shape its images are built for" : "");
  }
  if (r.linear_not_carried != size_t(-1)) {
    const Candidate &l = r.candidates[r.linear_not_carried], &k = r.candidates[r.chosen];
    std::printf("the linear model (%s) simulated the held-out rows better, RMSE %s against %s, but the rig's [model] "
                "shape (%s) cannot carry it: kept the best network of that shape, which its images are built for\n",
                l.arx ? "ARX" : "output-error", rmse(l).c_str(), rmse(k).c_str(), describe_layers(k.layers).c_str());
  }
}

std::string fmt_g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

Objective objective_of(const TrainArgs& a) {
  if (a.objective.empty()) return Objective::Simulation;
  if (a.objective != "simulation" && a.objective != "one-step")
    throw PipelineError("--objective must be simulation or one-step, got '" + a.objective + "'");
  return a.objective == "one-step" ? Objective::OneStep : Objective::Simulation;
}

// The longest history every controller holds for the rig's m, n and w.
int max_lags_of(const PlantTarget& target) {
  return std::max(1, std::min(HostCapacity::nd, (HostCapacity::inputs - target.w) / (target.m + target.n)));
}

// The rig's lags unless overridden, within what every controller holds;
// "auto" (or a rig file that leaves them out) searches them on the data.
// On a rig that searches, one length given sets both (the controller keeps
// one). True when they are searched: nd = dd = 1 until then.
bool apply_lags(const TrainArgs& a, const PlantTarget& target, TrainOptions& o) {
  const bool rig_auto = target.lags_auto && a.nd.empty() && a.dd.empty();
  const bool nd_auto = a.nd == "auto" || rig_auto, dd_auto = a.dd == "auto" || rig_auto;
  if ((nd_auto && !a.dd.empty() && !dd_auto) || (dd_auto && !a.nd.empty() && !nd_auto))
    throw PipelineError("--nd and --dd: give both lengths, or search both (\"auto\")");
  if (!nd_auto && !a.nd.empty()) o.nd = static_cast<int>(to_long("--nd", a.nd, 1, HostCapacity::nd));
  if (!dd_auto && !a.dd.empty()) o.dd = static_cast<int>(to_long("--dd", a.dd, 1, HostCapacity::nd));
  if (target.lags_auto && a.dd.empty() && !a.nd.empty() && !nd_auto) o.dd = o.nd;
  if (target.lags_auto && a.nd.empty() && !a.dd.empty() && !dd_auto) o.nd = o.dd;
  const bool search = nd_auto || dd_auto;
  if (search) o.nd = o.dd = 1;  // chosen once the runs are read
  if (const int p = o.nd * target.m + o.dd * target.n + target.w; p > HostCapacity::inputs)
    throw PipelineError(fmt::format("--nd {} --dd {}: the network's input p = nd m + dd n + w = {} exceeds {} for rig "
                                    "'{}' (m = {}, n = {}, w = {})",
                                    o.nd, o.dd, p, HostCapacity::inputs, target.name, target.m, target.n, target.w));
  return search;
}

// --arch, --hidden and --activation: the network's layers, sizes separated
// by '/' each a candidate, trained and judged.
void apply_architecture(const TrainArgs& a, const PlantTarget& target, TrainOptions& o) {
  // --arch names the first hidden layer's kind; the rest are Dense.
  const LayerKindInfo* first = &layer_kind_info(o.layers[0].kind);
  if (!a.arch.empty()) {
    first = nullptr;
    std::string names;
    for (const LayerKindInfo& k : kLayerKinds) {
      names += std::string(names.empty() ? "" : " or ") + k.name;
      if (a.arch == k.name) first = &k;
    }
    if (first == nullptr) throw PipelineError("--arch must be " + names + ", got '" + a.arch + "'");
  }
  const bool dense = first->kind == LayerKind::Dense;
  Activation hidden_act = Activation::Relu;
  if (!a.activation.empty() && !activation_from_name(a.activation, &hidden_act))
    throw PipelineError("--activation must be relu, tanh, sigmoid, hard_sigmoid or linear, got '" + a.activation +
                        "'");
  std::vector<std::vector<LayerSpec>> sizes;
  std::stringstream alternatives(a.hidden.empty() ? "5,5" : a.hidden);
  std::string one;
  while (std::getline(alternatives, one, '/')) {
    std::vector<int> units = to_units(one);
    if (!dense && units.empty())
      throw PipelineError(fmt::format("--arch {} needs at least one hidden size (the {} units)", first->name,
                                      first->title));
    std::vector<LayerSpec> layers;
    for (size_t i = 0; i < units.size(); ++i)
      layers.push_back(layer_spec(i == 0 ? first->kind : LayerKind::Dense, units[i], hidden_act));
    layers.push_back({LayerKind::Dense, target.n, units.empty() ? Activation::Linear : Activation::Tanh});
    sizes.push_back(layers);
  }
  if (sizes.empty()) throw PipelineError("--hidden needs a list like 5,5 (or 'none')");
  o.layers = sizes.front();
  o.alternatives.assign(sizes.begin() + 1, sizes.end());
  // One shape asked for is the shape wanted (an image built for it): a
  // linear model that wins is carried in it. Several ('/') are candidates.
  o.keep_shape = sizes.size() == 1;
}

// The start, the budgets, the optimiser's numbers and the loss.
void apply_training_options(const TrainArgs& a, TrainOptions& o) {
  if (!a.start.empty()) {
    if (a.start != "linear" && a.start != "random")
      throw PipelineError("--start must be linear or random, got '" + a.start + "'");
    o.start = a.start == "linear" ? Start::Linear : Start::Random;
  }
  if (!a.seeds.empty()) o.seeds = static_cast<int>(to_long("--seeds", a.seeds, 1, 64));
  if (!a.horizon.empty()) o.sim.horizon = static_cast<int>(to_long("--horizon", a.horizon, 2, 100000));
  if (!a.sim_epochs.empty()) o.sim.epochs = static_cast<int>(to_long("--sim-epochs", a.sim_epochs, 0, 100000));
  if (!a.lbfgs.empty()) o.sim.lbfgs_evals = static_cast<int>(to_long("--lbfgs", a.lbfgs, 0, 1000000));
  if (!a.epochs.empty()) o.epochs = static_cast<int>(to_long("--epochs", a.epochs, 1, 100000));
  if (!a.batch.empty()) o.batch = static_cast<int>(to_long("--batch", a.batch, 1, 1 << 20));
  if (!a.lr.empty()) o.lr = to_double("--lr", a.lr, 1e-9, 1.0);
  if (!a.seed.empty()) o.seed = static_cast<uint64_t>(to_long("--seed", a.seed, 0, 0x7fffffffL));
  if (!a.patience.empty()) o.patience = static_cast<int>(to_long("--patience", a.patience, 1, 100000));
  if (!a.y_noise.empty()) o.y_noise = to_double("--y-noise", a.y_noise, 0.0, 10.0);
  if (!a.loss.empty()) {
    if (a.loss != "mse" && a.loss != "huber") throw PipelineError("--loss must be mse or huber, got '" + a.loss + "'");
    o.loss = a.loss == "huber" ? Loss::Huber : Loss::Mse;
  }
  if (a.residual && a.absolute) throw PipelineError("--residual and --absolute exclude each other");
  if (a.residual) o.residual = true;
  if (a.absolute) o.residual = false;
}

// The history searched on the runs (linear models, then networks probed);
// o's lags set to it, and the words that say how it was chosen.
std::string choose_lags(const std::vector<Series>& runs, const PlantTarget& target, TrainOptions& o, int validate) {
  const int max_lags = max_lags_of(target);
  LagChoice lags = search_lags(runs, max_lags, o.folds, validate);
  {
    TrainProgress probe_bar(stderr);
    TrainOptions po = o;
    po.progress = [&probe_bar](const Progress& p) { probe_bar(p); };
    const InterruptGuard interrupt;
    po.stop = &interrupt.flag();
    lags = probe_network_lags(lags, runs, target, po, validate, max_lags, [&](int L, const std::string& what) {
      probe_bar.finish();
      std::fprintf(stderr, "history: trying nd = dd = %d with %s\n", L, what.c_str());
    });
    probe_bar.finish();
  }
  o.nd = o.dd = lags.lags;
  const std::string words = lags.words();
  std::printf("history: %s\n", words.c_str());
  std::fflush(stdout);  // before the progress on stderr, when both go to one file
  return words;
}

// What is trained on: the runs, their lengths and gaps, each one's first
// and last sample, and how their inputs' levels cover the range.
void print_training_runs(const std::vector<Series>& runs, const PlantTarget& target, const TrainOptions& o) {
  long samples = 0, gaps = 0;
  for (const Series& s : runs) samples += s.rows(), gaps += long(s.breaks.size());
  std::printf("training on %zu run%s of rig %s: %ld samples, %ld gap%s; nd = %d, dd = %d\n", runs.size(),
              runs.size() == 1 ? "" : "s", target.name.c_str(), samples, gaps, gaps == 1 ? "" : "s", o.nd, o.dd);
  for (const Series& s : runs) {
    if (s.rows() == 0) continue;
    const long last = s.rows() - 1;
    std::string first_row, last_row;
    for (int i = 0; i < s.m; ++i) first_row += " u" + std::to_string(i) + "=" + fmt_g(s.u(0, i)),
                                  last_row += " u" + std::to_string(i) + "=" + fmt_g(s.u(last, i));
    for (int j = 0; j < s.n; ++j) first_row += " y" + std::to_string(j) + "=" + fmt_g(s.y(0, j)),
                                  last_row += " y" + std::to_string(j) + "=" + fmt_g(s.y(last, j));
    // Its length in control steps at the rig's rate: a --sim-fast firmware's clock ran far faster than that.
    const std::string span = target.rate_hz > 0 ? fmt_g(double(s.rows()) / target.rate_hz) + " s at " + fmt_g(target.rate_hz) + " Hz"
                                                : fmt_g(s.time(last)) + " s";
    std::printf("  %s: %ld samples, %zu gap%s, %s; first%s; last%s\n", s.name.c_str(), s.rows(), s.breaks.size(),
                s.breaks.size() == 1 ? "" : "s", span.c_str(), first_row.c_str(), last_row.c_str());
  }
  for (const std::string& note : input_level_notes(runs)) std::printf("%s\n", note.c_str());
  std::fflush(stdout);
}

// The model written: its size and split, the test rows' errors and the fit's table.
void print_trained(const std::string& out, const PlantTarget& target, const TrainResult& r, const ModelFile& f,
                   const ModelFit& fit) {
  const std::string unit2 = target.y_unit.empty() ? std::string("units^2") : target.y_unit + "^2";
  // One-step epochs are the warm start's; a network started from the linear model had none.
  const std::string how = r.candidates.empty() || !r.candidates[r.chosen].linear_start
                              ? std::to_string(r.epochs_run) + " one-step epochs"
                              : "from the linear model";
  std::printf("trained %s model in %.1f s (%s), %s, rows train %ld / val %ld / test %ld\n",
              target.name.c_str(), r.seconds, how.c_str(),
              model_size_words(uint32_t(f.params.size()), f.view().norm_count()).c_str(),
              r.split.train_end, r.split.val_end - r.split.val_begin, r.split.test_end - r.split.test_begin);
  for (size_t j = 0; j < r.test.mse.size(); ++j)
    std::printf("test y%zu: MSE %.4e %s (RMSE %.4g), free-run MSE %.4e %s\n", j, r.test.mse[j], unit2.c_str(),
                std::sqrt(r.test.mse[j]), r.test.free_run_mse[j], unit2.c_str());
  ModelFit shown = fit;
  shown.lags.clear();  // printed before training
  std::printf("%s", fit_table(shown).c_str());
  if (const std::string why = float_gap_words(r, fit, target.y_unit); !why.empty()) std::printf("%s\n", why.c_str());
  std::printf("wrote %s, hash 0x%08x\n", out.c_str(), f.shape.hash);
}

// --plant: the stand-in a replay steps instead of the rig (plant_model.hpp),
// each part trained as a model is, on the same runs and options; its
// coupled free run of rows none was trained on is printed and kept in it.
void run_train_plant(const TrainArgs& a, const PlantTarget& target, const std::vector<Series>& runs, int validate) {
  if (validate >= 0)
    throw PipelineError("--plant holds out the last tenth of every run to measure the plant's free run: give its "
                        "runs as --run, not --validate-run");
  if (!(target.rate_hz > 0)) throw PipelineError("rig '" + target.name + "' states no control rate: a plant model steps at it");
  PlantModel pm;
  pm.rig = target.name;
  pm.m = target.m, pm.n = target.n, pm.w = target.w;
  pm.rate_hz = target.rate_hz;
  const std::vector<std::vector<int>> parts = plant_parts(target.n, target.w);
  std::printf("training a plant model of rig %s: its %d outputs and %d sensors, %d channels in %zu part%s of at most "
              "%d (a model file's outputs)\n",
              target.name.c_str(), target.n, target.w, target.n + target.w, parts.size(), parts.size() == 1 ? "" : "s",
              HostCapacity::n);
  const InterruptGuard interrupt;
  for (size_t i = 0; i < parts.size(); ++i) {
    const PlantTarget pt = part_target(target, runs, parts[i]);
    std::vector<Series> ps;
    for (const Series& s : runs) ps.push_back(part_series(s, parts[i]));
    TrainOptions o = default_options(pt, objective_of(a));
    if (apply_lags(a, pt, o)) o.nd = o.dd = std::max(2, std::min(target.nd, max_lags_of(pt)));
    if (!a.arch.empty() || !a.hidden.empty()) apply_architecture(a, pt, o);
    apply_training_options(a, o);
    std::string names;
    for (const std::string& nm : pt.y_names) names += (names.empty() ? "" : " ") + nm;
    std::printf("part %zu of %zu (%s) from the inputs, nd = %d, dd = %d\n", i + 1, parts.size(), names.c_str(),
                o.nd, o.dd);
    std::fflush(stdout);
    TrainProgress bar(stderr);
    o.progress = [&bar](const Progress& p) { bar(p); };
    o.stop = &interrupt.flag();
    const TrainResult r = train(ps, pt, o);
    bar.finish();
    const Candidate& c = r.candidates[r.chosen];
    std::printf("  kept %s, %zu weights (of %zu candidates, by their held-out free run)\n",
                c.arx ? "ARX" : describe_layers(c.layers).c_str(), c.weights, r.candidates.size());
    pm.parts.push_back({parts[i], r.model});
    if (r.stopped) break;
  }
  if (pm.parts.size() < parts.size()) throw PipelineError("stopped (Ctrl-C) before every part was trained: nothing written");
  pm.fit = plant_fit_words(plant_free_run(pm, runs), target);
  save_plant_model(a.out, pm);
  std::printf("plant model %s\nwrote %s: rig %s, %zu parts; replay a run through it: nlsoft-console runs replay ID "
              "--plant %s\n",
              pm.fit.c_str(), a.out.c_str(), target.name.c_str(), pm.parts.size(), a.out.c_str());
}

void run_train(const TrainArgs& a, const TargetResolver& resolve, const RunLoader& load_run) {
  need(a.rig, "--rig");
  if (a.data.empty() && a.runs.empty())
    throw PipelineError("give the data to train on: --run ID (a recorded run) or --data FILE.csv (see --help)");
  need(a.out, "--out");
  const PlantTarget target = resolve(a.rig);
  TrainOptions o = default_options(target, objective_of(a));
  const bool search = apply_lags(a, target, o);
  if (!a.arch.empty() || !a.hidden.empty()) apply_architecture(a, target, o);
  apply_training_options(a, o);

  int validate = -1;
  const std::vector<Series> runs = training_runs(a, target, load_run, &validate);
  for (const Series& s : runs) check_dimensions(s, target);
  if (a.plant) return run_train_plant(a, target, runs, validate);
  const std::string lag_words = search ? choose_lags(runs, target, o, validate) : "";
  print_training_runs(runs, target, o);
  TrainProgress bar(stderr);
  o.progress = [&bar](const Progress& p) { bar(p); };
  // Ctrl-C ends the training with the best model so far, which is written
  // as any other; a second Ctrl-C interrupts as usual.
  const InterruptGuard interrupt;
  o.stop = &interrupt.flag();
  const TrainResult r = train(runs, target, o, validate);
  bar.finish();
  print_choice(r, target.y_unit);
  ModelFile f = r.model;
  ModelFit fit = model_fit(r, target);
  fit.lags = lag_words.empty() ? fmt::format("nd = dd = {}, {}", o.nd, a.nd.empty() ? "the rig file's" : "given (--nd)")
                               : lag_words;
  f.fit = fit_to_json(fit);
  save_model_file(a.out, f);
  print_trained(a.out, target, r, f, fit);
}

// ---------------------------------------------------------------- model import
struct ImportArgs {
  std::string file, out, rig, dims, norm;
  bool residual = false;
};

std::vector<double> json_vector(const nlohmann::json& j, const char* key, size_t count, const std::string& name) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != count)
    throw PipelineError(name + ": '" + key + "' must be an array of " + std::to_string(count) + " numbers");
  std::vector<double> v;
  for (const auto& e : j[key]) {
    if (!e.is_number() || !std::isfinite(e.get<double>()))
      throw PipelineError(name + ": '" + key + "' holds a value that is not a finite number");
    v.push_back(e.get<double>());
  }
  return v;
}

void run_import(const ImportArgs& a, const TargetResolver& resolve) {
  need(a.file, "FILE.h5");
  need(a.out, "--out");
  if (!a.rig.empty() && !a.dims.empty()) throw PipelineError("give --rig or --dims, not both");
  const KerasNetwork k = read_keras_h5(a.file);
  // No guess from the input count: two rigs may share it.
  if (a.rig.empty() && a.dims.empty())
    throw PipelineError("give the rig the network is of: --rig NAME|PATH, or --dims m,n,w,nd,dd");
  ModelFile f;
  Model<HostCapacity>& M = f.shape;
  if (!a.dims.empty()) {
    std::vector<long> d;
    std::stringstream ss(a.dims);
    std::string part;
    while (std::getline(ss, part, ',')) d.push_back(to_long("--dims", part, 0, 255));
    if (d.size() != 5) throw PipelineError("--dims takes m,n,w,nd,dd (five integers)");
    M.m = uint8_t(d[0]);
    M.n = uint8_t(d[1]);
    M.w = uint8_t(d[2]);
    M.nd = uint8_t(d[3]);
    M.dd = uint8_t(d[4]);
  } else {
    const PlantTarget t = resolve(a.rig);
    M.m = uint8_t(t.m);
    M.n = uint8_t(t.n);
    M.w = uint8_t(t.w);
    M.nd = uint8_t(t.nd);
    M.dd = uint8_t(t.dd);
    f.platform = t.platform;
  }
  if (M.p() != k.inputs)
    throw PipelineError("the network takes " + std::to_string(k.inputs) + " inputs but the dimensions give p = " +
                        std::to_string(M.p()));
  if (k.layers.size() > size_t(HostCapacity::layers)) throw PipelineError("too many layers for the controller");
  M.residual = a.residual;
  M.layer_count = uint8_t(k.layers.size());
  for (size_t i = 0; i < k.layers.size(); ++i) M.layer[i] = k.layers[i];
  const size_t p = size_t(M.p()), n = size_t(M.n);
  std::vector<double> in_off(p, 0.0), in_sc(p, 1.0), out_off(n, 0.0), out_sc(n, 1.0);
  if (!a.norm.empty()) {
    const std::string text = read_text_file(a.norm, {"normalisation JSON file", 1u << 20});
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
    } catch (const std::exception& e) {
      throw PipelineError(a.norm + ": not valid JSON: " + e.what());
    }
    in_off = json_vector(j, "in_offset", p, a.norm);
    in_sc = json_vector(j, "in_scale", p, a.norm);
    out_off = json_vector(j, "out_offset", n, a.norm);
    out_sc = json_vector(j, "out_scale", n, a.norm);
  }
  for (double v : in_off) f.params.push_back(static_cast<float>(v));
  for (double v : in_sc) f.params.push_back(static_cast<float>(v));
  for (double v : out_off) f.params.push_back(static_cast<float>(v));
  for (double v : out_sc) f.params.push_back(static_cast<float>(v));
  f.params.insert(f.params.end(), k.weights.begin(), k.weights.end());
  if (M.n != k.layers.back().out)
    throw PipelineError("the last layer has " + std::to_string(k.layers.back().out) + " outputs but n = " +
                        std::to_string(M.n));
  save_model_file(a.out, f);
  std::printf("imported %s: %zu layers, %zu weights -> %s, hash 0x%08x\n", a.file.c_str(), k.layers.size(),
              k.weights.size(), a.out.c_str(), f.shape.hash);
}

// ---------------------------------------------------------------- model eval
void run_eval(const std::string& model, const std::string& input, const std::string& output) {
  need(model, "MODEL");
  need(input, "--input");
  need(output, "--output");
  const ModelFile f = load_model_file(model);
  const Model<HostCapacity> M = f.view();
  const Table in = read_csv(input, false);
  if (in.cols != M.p())
    throw PipelineError(input + ": rows have " + std::to_string(in.cols) + " values, the model takes p = " +
                        std::to_string(M.p()));
  Table out;
  out.cols = M.n;
  out.rows = in.rows;
  ForwardScratch<HostCapacity, float> scratch;
  float x[Dims<HostCapacity>::p], y[HostCapacity::n];
  for (long r = 0; r < in.rows; ++r) {
    for (int i = 0; i < M.p(); ++i) x[i] = static_cast<float>(in.at(r, i));
    forward(M, x, y, scratch);
    for (int j = 0; j < M.n; ++j) out.data.push_back(static_cast<double>(y[j]));
  }
  write_file_atomic(output, [&](std::ostream& os) { write_csv(os, out); });
  std::printf("evaluated %ld rows -> %s\n", in.rows, output.c_str());
}

// ---------------------------------------------------------------- model info
void run_info(const std::string& path, const PlatformNamer& name_platform) {
  need(path, "MODEL");
  const ModelFile f = load_model_file(path);
  const Model<HostCapacity> M = f.view();
  // A shipped rig's model carries its INFO number; the fit `train` keeps names any rig.
  const std::string shipped = name_platform(f.platform);
  const std::string rig = !shipped.empty() ? "rig " + shipped + " (shipped, platform " + std::to_string(f.platform) + ")"
                          : f.fit.empty() ? std::string("rig not named (a rig file's model kept no fit)")
                                          : "rig " + fit_from_json(f.fit, path).rig + " (a rig file)";
  std::printf("%s\n  %s, m=%d n=%d w=%d nd=%d dd=%d, p=%d inputs, %s output\n", path.c_str(), rig.c_str(), M.m,
              M.n, M.w, M.nd, M.dd, M.p(), M.residual ? "residual (y(k) + g(x))" : "absolute");
  uint32_t weights = 0;
  for (int i = 0; i < M.layer_count; ++i) {
    const Layer& L = M.layer[i];
    weights += layer_weight_count(L);
    const LayerKindInfo& kind = layer_kind_info(L.kind);
    std::printf("  %d  %-6s %3d -> %-3d %-12s %5u weights", i, kind.title, L.in, L.out, activation_name(L.act),
                layer_weight_count(L));
    if (kind.recurrent)
      std::printf(" (recurrent %s, reset_after %s)", activation_name(L.rec_act), L.reset_after ? "true" : "false");
    std::printf("\n");
  }
  std::printf("  parameters: %s\n  hash 0x%08x\n", model_size_words(weights + M.norm_count(), M.norm_count()).c_str(),
              M.hash);
  if (f.fit.empty())
    std::printf("no fit recorded (train keeps one; this model was imported or trained before)\n");
  else
    std::printf("%s", fit_table(fit_from_json(f.fit, path)).c_str());
}

}  // namespace

void add_dataset_command(CLI::App& app, TargetResolver resolve) {
  auto dataset_args = std::make_shared<DatasetArgs>();
  CLI::App* ds = app.add_subcommand(
      "dataset",
      "Record identification data from a rig's simulated plant into CSV (columns time,u0..,y0..,l0..).\n"
      "Random steps, smoothed random walks and chirps inside the input limits (plus the paper's\n"
      "u(t) = 1000 sin t cos t for msd), so the model sees the whole task space and how each input moves it.\n"
      "Example: nlsoft-console dataset --rig hasel --out hasel.csv --seed 1\n"
      "Any rig file with a [plant]: nlsoft-console dataset --rig lab/arm.toml --out arm.csv");
  add_rig_option(ds, dataset_args->rig, "the rig: a shipped rig's name or a rig file (required)");
  ds->add_option("--out", dataset_args->out, "CSV file to write (required; replaced atomically)")->type_name("FILE");
  ds->add_option("--steps", dataset_args->steps, "number of samples (default 120000)")->type_name("K");
  ds->add_option("--seed", dataset_args->seed, "seed of the excitation and the sensor noise (default 1)")->type_name("S");
  ds->callback([dataset_args, resolve] { run_dataset(*dataset_args, resolve); });
}

void add_train_command(CLI::App& app, TargetResolver resolve, RunLoader load_run) {
  auto train_args = std::make_shared<TrainArgs>();
  CLI::App* tr = app.add_subcommand(
      "train",
      "Train the forward model y(k+1) = g(u(k),u(k-1),y(k),y(k-1),l(k)) on recorded runs or a dataset\n"
      "and write a model file. By default it is trained for what the controller does with it,\n"
      "simulation: from the linear model (--start), the model is fed its own predictions over\n"
      "windows of --horizon steps (at least the rig's N) and its simulation error minimised (L-BFGS);\n"
      "the weights that simulate the validation rows best are kept, over --seeds seeds and every\n"
      "size given to --hidden (16/32: two candidates); train prints each candidate and which it kept.\n"
      "--objective one-step trains one step ahead only (the paper's way). Ctrl-C keeps the best so far. From a run: u, the measured output y_true, the sensors l and the time\n"
      "come from the run; a gap in it (lost telemetry, a link outage) cuts it, no history spans one.\n"
      "Ten-fold time-series split of each run: its last part tests, the part before validates (early\n"
      "stopping); --validate-run holds a whole run out instead (and the runs' validation part is\n"
      "reported apart). The fit, per output: RMSE, nRMSE of the output's span and fit %, one-step and\n"
      "free-run, on the held-out rows, beside a linear ARX baseline on the same lags fitted on the\n"
      "training rows; printed and kept in the model file (model info shows it, model fit measures\n"
      "it on other runs). Dimensions, input limits, output ranges, lags (--nd/--dd override them)\n"
      "and layers come from the rig file; defaults for the shipped\n"
      "rigs are the shipped models (app/models/README.md): msd linear residual, hasel Dense 5 relu,\n"
      "5 relu, 3 linear; tendon GRU(5), Dense 5 relu, 3 tanh; another rig: its [model] layers, else\n"
      "three candidates, Dense 16 relu or Dense 32 relu to n tanh, or one linear layer, residual\n"
      "when its controller feeds back measured outputs.\n"
      "Example: nlsoft-console train --rig msd --run 12 --run 13 --out msd-rig.nlsm\n"
      "         nlsoft-console train --rig hasel --data hasel.csv --out hasel.nlsm\n"
      "Any rig file: nlsoft-console train --rig lab/arm.toml --data arm.csv --out arm.nlsm");
  add_rig_option(tr, train_args->rig, "the rig: a shipped rig's name or a rig file (required)");
  tr->add_option("--data", train_args->data,
                 "CSV from 'dataset' (time,u0..,y0..,l0..) or of a recorded run as 'runs export ID --csv'\n"
                 "writes it (k,step,time_us,...); repeat for several")
      ->type_name("FILE");
  tr->add_option("--run", train_args->runs, "a recorded run (runs list); repeat for several")->type_name("ID");
  tr->add_option("--db", train_args->db, "the runs' database (default: the console's, as `runs list`)")
      ->type_name("FILE");
  tr->add_option("--validate-run", train_args->validate_run,
                 "hold this recorded run out, whole, for the fit (default: the last part of each run)")
      ->type_name("ID");
  tr->add_option("--nd", train_args->nd,
                 "input history length (default: the rig's nd; 1..32, with p = nd m + dd n + w <= 88), or auto: "
                 "searched on the data (ARX, then a network at a few lengths; the default where the rig file leaves nd out)")
      ->type_name("N|auto");
  tr->add_option("--dd", train_args->dd, "output history length (default: the rig's dd; 1..32, with p <= 88), or auto")
      ->type_name("N|auto");
  tr->add_option("--out", train_args->out, "model file to write (required; replaced atomically)")->type_name("FILE");
  tr->add_option("--arch", train_args->arch, "dense | gru: the first hidden layer's kind (shared/layer_kind.hpp), the rest Dense")->type_name("ARCH");
  tr->add_option("--hidden", train_args->hidden,
                 "hidden sizes, e.g. 5,5 (one shape: the model keeps it, carrying the linear model where that wins); 'none' = one linear layer; '/' between candidates: 16/16,16")
      ->type_name("LIST");
  tr->add_option("--activation", train_args->activation, "the hidden Dense layers' (default relu)")
      ->type_name("ACT");
  tr->add_option("--objective", train_args->objective, "simulation (default) | one-step")->type_name("OBJ");
  tr->add_option("--horizon", train_args->horizon,
                 "steps a simulation window runs on the model's own predictions (default: the larger of 64\n"
                 "and the rig's N)")
      ->type_name("H");
  tr->add_option("--start", train_args->start,
                 "where a network's weights start (simulation objective): linear (default): the linear\n"
                 "output-error model (least squares, then its own simulation error), carried through the\n"
                 "network's first n units of each hidden layer, so every seed refines one consistent map (a\n"
                 "linear output after Dense relu or linear hidden layers at least n wide; others start at\n"
                 "random); random: the one-step warm start from random weights")
      ->type_name("FROM");
  tr->add_option("--seeds", train_args->seeds, "seeds tried per size, the best kept (default: 4 for a rig with [model] layers, 2 for one\n"
                 "without, whose two widths make four networks too; one-step: 1)")->type_name("K");
  tr->add_option("--sim-epochs", train_args->sim_epochs, "Adam epochs on the simulation objective before L-BFGS (default 0)")
      ->type_name("E");
  tr->add_option("--lbfgs", train_args->lbfgs, "L-BFGS evaluations at most (default: 15 million simulated steps in all,\n"
                 "from 50 to 2000; 0: none)")
      ->type_name("K");
  tr->add_option("--epochs", train_args->epochs, "maximum one-step epochs (the warm start; default 200)")->type_name("E");
  tr->add_option("--batch", train_args->batch, "mini-batch size (default 64)")->type_name("B");
  tr->add_option("--lr", train_args->lr, "Adam learning rate (default 3e-3, halved on plateaus)")->type_name("LR");
  tr->add_option("--loss", train_args->loss, "mse | huber (default mse)")->type_name("LOSS");
  tr->add_option("--seed", train_args->seed, "weight init and shuffling seed (default 1)")->type_name("S");
  tr->add_option("--patience", train_args->patience, "stop after this many epochs without a better validation loss")->type_name("P");
  tr->add_option("--y-noise", train_args->y_noise,
                 "sigma of noise added to the y-history inputs while training (normalised units),\n"
                 "(one-step objective: 0.05 by default for a rig fed its own predictions, so the model survives\n"
                 "its own predictions; simulation objective: 0.05 in the warm start, 0 for a residual model)")
      ->type_name("SIGMA");
  tr->add_flag("--residual", train_args->residual, "predict y(k+1) - y(k) (default for msd and for a rig fed back measured outputs)");
  tr->add_flag("--plant", train_args->plant,
              "train a plant model instead (FILE.nlsp): a stand-in for the rig that predicts its outputs and\n"
              "its sensors from the inputs, for `runs replay ID --plant FILE` of a board's runs; larger than\n"
              "the controller's model (the candidates of a rig without [model] layers), in parts of at most 6\n"
              "channels; its\n"
              "free run of the last tenth of each run, which it is not trained on, is printed and kept in it");
  tr->add_flag("--absolute", train_args->absolute, "predict y(k+1) directly (default for hasel, tendon)");
  tr->callback([train_args, resolve, load_run] { run_train(*train_args, resolve, load_run); });
}

void add_model_command(CLI::App& app, TargetResolver resolve, PlatformNamer name_platform, RunLoader load_run,
                       ScriptPlotter plot) {
  CLI::App* model = app.add_subcommand("model", "Inspect, evaluate, judge (fit), import and compile model files (.nlsm).");
  model->require_subcommand(1);

  auto import_args = std::make_shared<ImportArgs>();
  CLI::App* im = model->add_subcommand(
      "import",
      "Convert a Keras HDF5 Sequential model (InputLayer, Flatten, Dense, GRU, Dropout) to a model file.\n"
      "The dimensions come from the rig (--rig) or --dims.\n"
      "Normalisation is the identity unless --norm gives a JSON file with in_offset[p], in_scale[p],\n"
      "out_offset[n], out_scale[n].\n"
      "Example: nlsoft-console model import hasel.h5 --out hasel.nlsm --rig hasel");
  im->add_option("file", import_args->file, "Keras .h5 file (required)")->type_name("FILE.h5");
  im->add_option("--out", import_args->out, "model file to write (required)")->type_name("FILE");
  add_rig_option(im, import_args->rig, "the rig the network is of: a shipped rig's name or a rig file");
  im->add_option("--dims", import_args->dims, "m,n,w,nd,dd")->type_name("m,n,w,nd,dd");
  im->add_option("--norm", import_args->norm, "normalisation JSON")->type_name("FILE.json");
  im->add_flag("--residual", import_args->residual, "the network predicts y(k+1) - y(k)");
  im->callback([import_args, resolve] { run_import(*import_args, resolve); });

  auto eval_args = std::make_shared<std::array<std::string, 3>>();
  CLI::App* ev = model->add_subcommand(
      "eval",
      "Run a model on input vectors: one row of p values per line (no header), one row of n outputs\n"
      "written per input; each row independent (a GRU starts from a zero state).\n"
      "Example: nlsoft-console model eval hasel.nlsm --input x.csv --output y.csv");
  ev->add_option("model", (*eval_args)[0], "model file (required)")->type_name("MODEL");
  ev->add_option("--input", (*eval_args)[1], "CSV of input vectors (required)")->type_name("FILE");
  ev->add_option("--output", (*eval_args)[2], "CSV to write (required)")->type_name("FILE");
  ev->callback([eval_args] { run_eval((*eval_args)[0], (*eval_args)[1], (*eval_args)[2]); });

  auto info_path = std::make_shared<std::string>();
  CLI::App* in = model->add_subcommand("info", "Print a model's layers, shapes, parameter count and hash.");
  in->add_option("model", *info_path, "model file (required)")->type_name("MODEL");
  in->callback([info_path, name_platform] { run_info(*info_path, name_platform); });

  add_model_fit_command(*model, resolve, name_platform, load_run, plot);
}

}  // namespace nlsoft::console
