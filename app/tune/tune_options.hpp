#pragma once
// What a tuning session is asked to do, and its one text form, shared by the
// script command and the TUI's `:tune` (the command line's --options map
// onto the same fields):
//   tune Lambda=0.01..100:log Q*=0.1..1000:log objective="nrmse + 0.1*u_effort"
//        budget=40 budget=10min reference=swirl settle=1s window=5s seed=1
//        method=bobyqa max_saturated=0.5 save=best.params apply
//   tune replay=last Q*=0.1..1000:log apply     (replays of a recorded run)
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/tune/search_space.hpp"

namespace nlsoft::console {

struct TuneOptions {
  std::vector<Dimension> dims;
  std::string objective = "nrmse";
  int budget_runs = 40;     // evaluations; 0: only the time budget counts
  double budget_s = 0;      // wall time; 0: none
  std::string reference;    // a preset and overrides, "swirl hold=1" (as ref takes them); "": the one selected
  double settle_s = 1.0;    // each run settles this long before it is measured ...
  double window_s = 5.0;    // ... over this window
  std::string method = "bobyqa";  // or "neldermead"
  unsigned long seed = 1;
  // A run whose inputs sit at a limit in more than this share of the window
  // scores as failed.
  double max_saturated = 0.5;
  std::string save;  // "": tune-<session>.params
  bool apply = false;
  bool window_given = false;  // window= (or --window) said; a replay's default is the rest of its run
  // replay=N (replay=last: the session's last finished run): each candidate
  // is evaluated on a replay of recorded run N in this process, as `tune
  // --replay N` does; model=FILE the model those replays run, plant=FILE the
  // plant model they step in the rig's place (a board's run).
  int64_t replay = 0;
  bool replay_last = false;
  std::string model, plant;
  bool on_replays() const { return replay > 0 || replay_last; }
};

// Budget text: "40", "40 runs" (evaluations), "10min", "10 min", "90s" (wall time).
// Returns true for a number of runs. Throws std::invalid_argument.
bool set_budget(TuneOptions& o, const std::string& text);

// Checks what can be checked before connecting: the objective's syntax and
// metrics, the ranges' syntax, the method, the numbers. Throws
// std::invalid_argument in words.
void validate(const TuneOptions& o);

// The script form (the words after `tune`). Throws std::invalid_argument.
TuneOptions parse_tune_words(const std::vector<std::string>& words);

// Help lines for --help, F1 and `:help`.
const std::vector<std::string>& tune_help();

}  // namespace nlsoft::console
