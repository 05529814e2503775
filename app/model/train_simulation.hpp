#pragma once
// Training for what the model is used for: free-run simulation. After a
// one-step warm start, optionally Adam on mini-batches of H-step windows of
// the simulation objective (app/model/simulation_error.hpp) with a cosine
// learning rate, then full-batch L-BFGS (LBFGS++) on a fixed set of
// windows. L-BFGS alone is the default: on the cascaded tanks and the
// Silverbox it simulated the test sets better than Adam first (Adam's
// epochs, each judged on the validation rows, chose one that fitted those
// rows by chance).
// Every epoch and every L-BFGS evaluation is judged by free-run simulation
// of the validation rows, and the weights that simulated them best are kept:
// one-step loss says little about a model that is fed its own outputs.
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "app/model/simulation_error.hpp"

namespace nlsoft::model {

struct SimulationOptions {
  int horizon = 64;      // H, steps per window
  int epochs = 0;        // Adam epochs at most (0: straight to L-BFGS, the default)
  int batch = 16;        // windows per Adam step
  double lr = 2e-3;      // Adam's rate at the start of the cosine schedule
  int patience = 40;     // Adam epochs without a better validation free run
  // L-BFGS objective evaluations at most (0: none); -1: 15 million
  // simulated steps in all, from 50 to 2000 evaluations (120 000 rows: 125;
  // the cascaded tanks' 1000: 2000, where 300 left them at 0.44 V instead
  // of 0.36 V), so a large data set trains in minutes, not hours.
  int lbfgs_evals = -1;
  uint64_t seed = 1;
  int threads = 2;       // L-BFGS's full-batch passes split over this many threads
  const std::atomic<bool>* stop = nullptr;  // set: finish with the best weights so far
};

struct SimulationReport {
  double start_val = 0, best_val = 0;  // validation free-run loss at the warm start and at the end
  int epochs = 0, evals = 0;           // Adam epochs and L-BFGS evaluations run
};

// phase ("simulation", "L-BFGS"), step, steps, train loss, validation free-run loss, best so far.
using SimulationProgress = std::function<void(const char*, int, int, double, double, double)>;

// The L-BFGS evaluations a training of `rows` rows gets (o.lbfgs_evals, or
// its -1 rule above).
int lbfgs_budget(const SimulationOptions& o, long rows);

// Improves net (the warm start) in place; net ends with the best weights
// by validation free run, which may be the warm start's own.
SimulationReport fit_simulation(Network& net, const SimulationData& s, const std::vector<RowRange>& train,
                                const std::vector<RowRange>& val, const SimulationOptions& o,
                                const SimulationProgress& progress);

}  // namespace nlsoft::model
