#pragma once
// The tuning loop: NLopt proposes a point, the firmware runs it, the run's
// metrics score it. Each evaluation is an ordinary recorded run (labelled
// "tune S #k"): the reference restarted from its first point with the
// actuators neutral (RUN_START), settle_s to settle, then the metrics over
// window_s, so evaluations compare like sweep rows do.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "app/record/run_metrics.hpp"
#include "app/tune/search_space.hpp"
#include "app/tune/tune_options.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

class LiveConsole;

struct TuneEvaluation {
  int eval = 0;               // 1, 2, ...
  int budget = 0;             // runs budget (0: time only)
  int64_t run_id = 0;         // 0: refused before a run
  std::string point;          // "Lambda=0.5 Q*=12"
  double objective = 0;       // NaN when failed
  std::string failed;         // why, when failed
  double nrmse = 0;
  double best = 0;            // best objective so far (NaN: none yet)
  int best_eval = 0;
};

struct TuneResult {
  int64_t session = 0;
  int evaluations = 0, failures = 0;
  bool have_best = false;
  double best_objective = 0, start_objective = 0;  // start: NaN if the start failed
  int best_eval = 0;
  int64_t best_run = 0;
  std::string best_point;
  std::vector<SearchSpace::Write> best_values;
  RunMetrics best_metrics;
  std::string end_reason;  // "budget of 40 runs used", "interrupted", ...
  std::string saved_to;    // "" when nothing was saved
  bool applied = false;
  double wall_s = 0;
  std::vector<std::string> warnings;  // what makes the session's scores doubtful (motion_check.hpp)
};

struct TuneCallbacks {
  std::function<void(const std::string&)> out;                           // report lines
  std::function<void(const std::string&, size_t, size_t)> progress;      // the run in progress
  std::function<void(const TuneEvaluation&)> evaluated;                  // after each evaluation
};

// The session's reference option, "swirl hold=1" (a preset and its
// overrides, as `ref` takes them), for the connected firmware. Throws
// CliError.
RefParams tune_reference(LiveConsole& console, const std::string& text);

// Runs a whole session on the connected firmware. Ends at the budget, when
// NLopt converges, at Ctrl-C (interrupted()) or when *cancel
// turns true; in every case the best set found is printed and written with
// `params save`, and the searched parameters are put back as they were
// unless options.apply. Throws CliError on a bad parameter or range (before
// any run) and on a link or recording failure (after restoring).
TuneResult run_tuning(LiveConsole& console, const TuneOptions& options, const TuneCallbacks& cb,
                      const std::atomic<bool>* cancel = nullptr);

}  // namespace nlsoft::console
