#pragma once
// How a tuning session's candidates are evaluated, kept apart from the
// search (tuner.hpp): the search, its objective, bounds, failures, lines
// and budget are one, whether a candidate runs on the connected firmware
// (live_evaluator.hpp: a recorded run each) or on a replay of a recorded
// run of the simulator in this process (replay_evaluator.hpp).
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "app/record/run_metrics.hpp"
#include "app/tune/search_space.hpp"
#include "app/tune/tune_options.hpp"
#include "app/tune/tune_result.hpp"

namespace nlsoft::console {

// What one candidate did.
struct TuneOutcome {
  int64_t run_id = 0;       // the run recorded for it (0: none)
  std::string refused;      // the firmware refused its values (cross-parameter rules): its words; no run
  std::string ended_early;  // the run ended before its time: why
  RunMetrics metrics;       // over the window scored (settle .. settle + window)
};

class TuneEvaluator {
 public:
  using Progress = std::function<void(size_t done, size_t total)>;
  virtual ~TuneEvaluator() = default;

  // The parameters the search space is resolved against, and its start.
  virtual ParamSource& params() = 0;
  // Each output's span (the rig's task space): what "the reference barely
  // moves" is measured against; empty when unknown.
  virtual std::vector<double> task_space() const = 0;

  // The session begins (recorded, when it is): its id, 0 for none.
  virtual int64_t begin(const std::string& objective, const std::string& space, const std::string& method) = 0;
  // How the session's lines name it: "tuning session 3".
  virtual std::string name() const = 0;
  // What an evaluation is, in a line, for the session's start.
  virtual std::string evaluation_words(const TuneOptions& o) const = 0;
  // One candidate (every parameter it touches, whole) in force and run,
  // labelled for evaluation `eval`. A refusal of its values is an outcome;
  // a link, recording or internal failure throws (CliError).
  virtual TuneOutcome evaluate(const std::vector<SearchSpace::Write>& point, int eval, const Progress& progress,
                               const std::atomic<bool>* cancel) = 0;
  // An evaluation scored (or failed): kept beside its run, when it has one.
  virtual void scored(const TuneEvaluation& e, const std::string& objective) = 0;
  // The search over: the best set (r.have_best) kept as this evaluator
  // keeps it (saved to a file; left in force or put back; recorded), r's
  // saved_to, applied and best_run set. What went wrong doing so, or "".
  virtual std::string keep(TuneResult& r, const std::vector<SearchSpace::Write>& original) = 0;
  // The session's end recorded; never throws.
  virtual void finish(const TuneResult& r) = 0;
  // The lines after "best: ..." once the best is kept, and the line when no
  // evaluation succeeded.
  virtual std::vector<std::string> kept_words(const TuneResult& r) = 0;
  virtual std::string nothing_kept_words() const = 0;
};

}  // namespace nlsoft::console
