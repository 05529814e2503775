#pragma once
// Training of the forward model (paper, "Learning Forward Kinematics").
// By default for what the controller uses it for, simulation: a one-step
// warm start (Adam on mini-batches, MSE or Huber loss in normalised units,
// early stopping on the validation chunk of the ten-fold time-series split),
// then the simulation objective (app/model/train_simulation.hpp), judged by
// free-run simulation of the validation rows. A few candidates (seeds and
// sizes) are trained and the one that simulates the validation rows best is
// kept. `Objective::OneStep` stops after the warm start (the paper's way).
// Everything is seeded: one seed, one model, bit for bit, however many
// threads train the candidates.
//
// Residual mode trains the network on y(k+1) - y(k) (the model file's
// residual flag adds y(k) back), which suits plants whose output moves little
// per step (msd at 1 kHz). `y_noise` perturbs the y-history inputs while
// training (and the residual base with them), which teaches the network to
// lean on the sensors: the soft rigs run with the y-queue fed by the model's
// own predictions, whose errors must fade rather than accumulate.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "app/model/arx.hpp"
#include "app/model/dataset.hpp"
#include "app/model/model_store.hpp"
#include "app/model/network.hpp"
#include "app/model/plant_target.hpp"
#include "app/model/train_simulation.hpp"

namespace nlsoft::model {

enum class Loss { Mse, Huber };
enum class Objective { OneStep, Simulation };
// Where a network candidate's weights start before the simulation objective:
// the one-step warm start from random weights, or the linear output-error
// model carried through the network (app/model/linear_start.hpp), for a
// network that can hold it (a linear output; others start at random).
enum class Start { Random, Linear };

struct Progress {
  const char* phase = "one-step";  // "one-step", "simulation", "L-BFGS"
  int candidate = 0, candidates = 1;  // candidate -1: the linear model the networks start from
  int epoch = 0, epochs = 0;
  double train_loss = 0, val_loss = 0, best_val = 0, lr = 0;
  double elapsed_s = 0, eta_s = 0;
};

// One network tried: its layers and seed, and how well it simulated the
// training and validation rows, each stretch from its measured start
// (MSE / variance, app/model/simulation_error.hpp).
struct Candidate {
  std::vector<LayerSpec> layers;
  uint64_t seed = 1;
  double val_free_run = 0;     // after training: what stopped its training (training and validation rows)
  double warm_free_run = 0;    // where training started: after the warm start, or the linear model's
  // What chose among the candidates: the free run of the held-out rows, which
  // no candidate was fitted on or stopped by (MSE / variance over outputs),
  // and its RMSE per output in the outputs' units (the held-out table's).
  double held_out = 0;
  std::vector<double> held_out_rmse;
  bool linear_start = false;   // started from the linear model (Start::Linear)
  bool arx = false;            // the least-squares linear model (ARX on the same lags), no simulation training
  int one_step_epochs = 0;     // the warm start's (0: started from the linear model)
  int epochs = 0, evals = 0;   // simulation epochs, L-BFGS evaluations
  size_t weights = 0;
  bool is_network() const;     // hidden layers: more than the linear model
};
std::string describe_layers(const std::vector<LayerSpec>& layers);

struct TrainOptions {
  std::vector<LayerSpec> layers;
  int nd = 2, dd = 2;
  int epochs = 200;
  int batch = 64;
  double lr = 3e-3;
  Loss loss = Loss::Mse;
  double huber_delta = 0.1;  // normalised output units
  uint64_t seed = 1;
  bool residual = false;
  int patience = 25;         // epochs without a better validation loss
  double y_noise = 0.0;      // sigma of the y-history perturbation, normalised input units
  int folds = 10;
  Objective objective = Objective::Simulation;
  SimulationOptions sim;     // the simulation objective's (its seed is each candidate's)
  Start start = Start::Linear;  // every network that can hold the linear model starts from it
  // Other sizes tried beside `layers`, and seeds per size (seed, seed+1, ...).
  std::vector<std::vector<LayerSpec>> alternatives;
  int seeds = 1;
  // The first of `layers` is the shape the rig's images are built for (its
  // [model]): a linear model that wins is carried in that shape where it can
  // be (app/model/linear_start.hpp), else the best network of it is kept.
  bool keep_shape = false;
  int threads = 2;           // candidates trained at once
  const std::atomic<bool>* stop = nullptr;  // set (Ctrl-C): finish with the best model so far
  std::function<void(const Progress&)> progress;
};

// The trainer's own view of the finished model: network, normalisation, and
// the evaluation in double that the export must reproduce.
struct TrainedNetwork {
  Network net;
  Normalisation nz;
  InputLayout layout{};
  bool residual = false;

  Eigen::MatrixXd predict(const Eigen::MatrixXd& X_raw) const;  // rows x n, physical units
  ModelFile export_model(uint8_t platform) const;
};

struct Evaluation {
  std::vector<double> mse;           // one-step, per output, physical units squared
  std::vector<double> free_run_mse;  // y-queue fed with the model's own predictions
  long rows = 0;                     // rows evaluated
};

// Runs the exported model exactly as the firmware does (shared/forward.hpp,
// float) over dataset rows [begin, end), or over pieces of consecutive rows
// (the free run starts again from the measured outputs at each piece).
Evaluation evaluate(const ModelFile& model, const Dataset& d, long begin, long end);
Evaluation evaluate(const ModelFile& model, const Dataset& d, const std::vector<RowRange>& pieces);

struct TrainResult {
  TrainedNetwork trained;
  ModelFile model;
  Evaluation test;
  std::string held_out;  // which rows the test evaluated, in words
  double best_val_loss = 0;
  int epochs_run = 0;
  double seconds = 0;
  Partition split{};  // over the rows of every run: all training rows, then validation, then test
  // The pooled rows (split as above) and, within them, the pieces each
  // part is: what the fit (app/model/model_fit.hpp) scores.
  Dataset data;
  std::vector<RowRange> val_pieces, test_pieces;
  bool validate_run = false;  // the test is a whole run held out
  int folds = 10;
  // The linear baseline on the same lags, fitted on the training rows.
  ArxModel arx;
  // Every candidate trained, and the index of the one kept: the best free
  // run of the held-out rows (the rows of the held-out table, `test_pieces`),
  // the least-squares ARX model and the linear output-error model always
  // among them; on a tie, the one with fewer weights. A network kept has
  // simulated the held-out rows better than both.
  std::vector<Candidate> candidates;
  size_t chosen = 0;
  // The best network's index when a linear model beat it (else npos): train
  // says so.
  size_t beaten_network = static_cast<size_t>(-1);
  // With keep_shape: the linear candidate carried in the rig's shape (the
  // kept candidate is then that carrier), or the linear candidate that won
  // but which the shape cannot carry (the best network was kept). npos: neither.
  size_t carried_linear = static_cast<size_t>(-1);
  size_t linear_not_carried = static_cast<size_t>(-1);
  Objective objective = Objective::Simulation;
  bool stopped = false;  // cut short by TrainOptions::stop
};

// Throws PipelineError when the series does not match the rig, or the
// options are unusable. The rig: its dimensions, input limits and the
// middle of its outputs' ranges (the rig file's, no simulated plant).
TrainResult train(const Series& s, const PlantTarget& target, const TrainOptions& opt);
// Several runs of one rig. Each run is split as one series is (ten-fold
// time-series split: its last part tests, the part before validates), and
// the parts are pooled; with validate >= 0 that run is the test, whole, and
// the others keep their last part for validation.
TrainResult train(const std::vector<Series>& runs, const PlantTarget& target, const TrainOptions& opt,
                  int validate = -1);
// Throws PipelineError, naming the series, when its m, n, w are not the rig's.
void check_dimensions(const Series& s, const PlantTarget& target);

// A rig's: its [model] layers and history length over the defaults of its
// plant (a named plant's shipped model, else Dense 16 relu -> n tanh, with
// Dense 32 relu -> n tanh and one linear layer as other candidates).
TrainOptions default_options(const PlantTarget& target, Objective objective = Objective::Simulation);

}  // namespace nlsoft::model
