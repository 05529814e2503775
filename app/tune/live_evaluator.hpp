#pragma once
// A tuning session on the connected firmware (a board, QEMU or the
// simulator): each candidate put in force and run as an ordinary recorded
// run (labelled "tune S #k"): the reference restarted from its first point
// with the actuators neutral (RUN_START), settle_s to settle, then the
// metrics over window_s, so evaluations compare like sweep rows do. The
// session and its evaluations go to the recording's tuning tables; the best
// set is saved with `params save` and left in force or put back.
#include <memory>

#include "app/live/live_console.hpp"
#include "app/record/tune_log.hpp"
#include "app/tune/evaluator.hpp"
#include "app/tune/live_param_source.hpp"

namespace nlsoft::console {

class LiveEvaluator final : public TuneEvaluator {
 public:
  LiveEvaluator(LiveConsole& console, const TuneOptions& o) : console_(console), o_(o), params_(console) {}

  ParamSource& params() override { return params_; }
  std::vector<double> task_space() const override;
  int64_t begin(const std::string& objective, const std::string& space, const std::string& method) override;
  std::string name() const override;
  std::string evaluation_words(const TuneOptions& o) const override;
  TuneOutcome evaluate(const std::vector<SearchSpace::Write>& point, int eval, const Progress& progress,
                       const std::atomic<bool>* cancel) override;
  void scored(const TuneEvaluation& e, const std::string& objective) override;
  std::string keep(TuneResult& r, const std::vector<SearchSpace::Write>& original) override;
  void finish(const TuneResult& r) override;
  std::vector<std::string> kept_words(const TuneResult& r) override;
  std::string nothing_kept_words() const override;

 private:
  LiveConsole& console_;
  const TuneOptions& o_;
  LiveParamSource params_;
  std::unique_ptr<TuneLog> log_;
  int64_t session_ = 0;
};

}  // namespace nlsoft::console
