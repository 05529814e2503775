#pragma once
// The tuning loop: NLopt proposes a point, an evaluator runs it (the
// connected firmware, live_evaluator.hpp, or a replay in this process,
// replay_evaluator.hpp), its metrics over the window score it.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "app/tune/evaluator.hpp"
#include "app/tune/search_space.hpp"
#include "app/tune/tune_options.hpp"
#include "app/tune/tune_result.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

class LiveConsole;

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

// The same session with each candidate evaluated by `evaluator`; the
// options checked, the search space resolved against its parameters. Ends
// and keeps the best as above, by the evaluator's means.
TuneResult run_tuning(TuneEvaluator& evaluator, const TuneOptions& options, const TuneCallbacks& cb,
                      const std::atomic<bool>* cancel = nullptr);

}  // namespace nlsoft::console
