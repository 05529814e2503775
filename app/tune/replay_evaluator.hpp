#pragma once
// A tuning session on replays of a recorded run of the simulator (`tune
// --replay N`): each candidate is run N again in this process (replay_run:
// the simulator's firmware and plant, the run's reference, model and
// parameters at its start, the candidate on top), as fast as the host goes,
// with no rig, port or simulator process. The candidates' replays go to a
// scratch database of their own, deleted at the end, since only their
// figures matter; the best is replayed once more into the recording as a
// run of kind `replay` (unless told not to record), and its whole set is
// saved as `params save` writes one. Figures are the simulator's plant, not
// the rig's, and are said to be.
#include <memory>
#include <string>
#include <vector>

#include "app/record/recorder.hpp"
#include "app/replay/replay_run.hpp"
#include "app/replay/replay_source.hpp"
#include "app/tune/evaluator.hpp"

namespace nlsoft::console {

// The scored window inside run `src`: settle= and window= must fit in it;
// with no window given (o.window_given false), the rest of the run after
// settle. Throws CliError naming the run and its length.
void fit_window_to_run(const ReplaySource& src, TuneOptions& o);

class ReplayEvaluator final : public TuneEvaluator {
 public:
  // src: run N, opened and checked (open_replay_source). record_best: the
  // best's replay recorded into src.db. Throws CliError (the model not the
  // run's, a recorded parameter the simulator refuses).
  ReplayEvaluator(const ReplaySource& src, const TuneOptions& o, bool record_best);
  ~ReplayEvaluator() override;

  ParamSource& params() override;
  std::vector<double> task_space() const override;
  int64_t begin(const std::string& objective, const std::string& space, const std::string& method) override;
  std::string name() const override;
  std::string evaluation_words(const TuneOptions& o) const override;
  TuneOutcome evaluate(const std::vector<SearchSpace::Write>& point, int eval, const Progress& progress,
                       const std::atomic<bool>* cancel) override;
  void scored(const TuneEvaluation&, const std::string&) override {}
  std::string keep(TuneResult& r, const std::vector<SearchSpace::Write>& original) override;
  void finish(const TuneResult&) override {}
  std::vector<std::string> kept_words(const TuneResult& r) override;
  std::string nothing_kept_words() const override;

  // The plant's noise seed of every replay: the simulator's default, which
  // a --sim run does not record (as `runs replay` without --seed).
  static constexpr uint32_t kNoiseSeed = 1;

 private:
  class Params;
  // A candidate's replay into `recorder`: its run id, or the refusal.
  TuneOutcome replay(const std::vector<SearchSpace::Write>& point, Recorder& recorder, const std::string& db,
                     const std::string& label, const std::string& notes, const Progress& progress);

  const ReplaySource& src_;
  const TuneOptions& o_;
  bool record_best_;
  std::unique_ptr<Params> params_;
  std::string scratch_dir_, scratch_db_;
  std::unique_ptr<Recorder> scratch_;
  RunMetrics recorded_;  // run N's own figures over the same window
  RunMetrics best_;      // the best's, from its recorded replay (else its evaluation's)
};

}  // namespace nlsoft::console
