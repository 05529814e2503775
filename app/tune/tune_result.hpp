#pragma once
// What a tuning session reports: each evaluation as it is scored, and the
// session's end (its best point, how it ended, what was kept).
#include <cstdint>
#include <string>
#include <vector>

#include "app/record/run_metrics.hpp"
#include "app/tune/search_space.hpp"

namespace nlsoft::console {

struct TuneEvaluation {
  int eval = 0;               // 1, 2, ...
  int budget = 0;             // runs budget (0: time only)
  int64_t run_id = 0;         // 0: refused before a run, or not recorded (a replay)
  std::string point;          // "Lambda=0.5 Q*=12"
  double objective = 0;       // NaN when failed
  std::string failed;         // why, when failed
  double nrmse = 0;
  double best = 0;            // best objective so far (NaN: none yet)
  int best_eval = 0;
};

struct TuneResult {
  int64_t session = 0;     // the session's id in the recording (0: none, a replay's)
  int evaluations = 0, failures = 0;
  bool have_best = false;
  double best_objective = 0, start_objective = 0;  // start: NaN if the start failed
  int best_eval = 0;
  int64_t best_run = 0;    // the best's recorded run (0: none)
  std::string best_point;
  std::vector<SearchSpace::Write> best_values;
  RunMetrics best_metrics;
  std::string end_reason;  // "budget of 40 runs used", "interrupted", ...
  std::string saved_to;    // "" when nothing was saved
  bool applied = false;
  double wall_s = 0;
  std::vector<std::string> warnings;  // what makes the session's scores doubtful (motion_check.hpp)
};

}  // namespace nlsoft::console
