#include "app/tune/live_evaluator.hpp"

#include <fmt/format.h>

#include "app/link/link_error.hpp"
#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::RigOutput;

namespace {

void put_in_force(LiveConsole& console, const std::vector<SearchSpace::Write>& writes) {
  for (const auto& [info, values] : writes) console.params().apply(info, values);
}

}  // namespace

std::vector<double> LiveEvaluator::task_space() const {
  // The console's rig, shipped or a rig file.
  std::vector<double> task;
  for (const RigOutput& output : console_.rig().outputs) task.push_back(output.span);
  return task;
}

int64_t LiveEvaluator::begin(const std::string& objective, const std::string& space, const std::string& method) {
  log_ = std::make_unique<TuneLog>(console_.db_path());
  session_ = log_->begin(objective, space, method);
  return session_;
}

std::string LiveEvaluator::name() const { return fmt::format("tuning session {}", session_); }

std::string LiveEvaluator::evaluation_words(const TuneOptions& o) const {
  return fmt::format("each evaluation is a recorded run: the reference from its first point, {:g} s to settle, "
                     "measured over {:g} s; failed if the watchdog trips, a frame is lost or the inputs sit at a "
                     "limit over {:g} % of it",
                     o.settle_s, o.window_s, 100 * o.max_saturated);
}

TuneOutcome LiveEvaluator::evaluate(const std::vector<SearchSpace::Write>& point, int eval, const Progress& progress,
                                    const std::atomic<bool>* cancel) {
  TuneOutcome out;
  try {
    put_in_force(console_, point);
  } catch (const NackError& refused) {
    // The firmware's cross-parameter rules: the point is outside the
    // feasible set, which is a result, not an error.
    out.refused = refused.what();
    return out;
  }
  const RunSummary s =
      console_.runs().run_for(o_.settle_s + o_.window_s, fmt::format("tune {} #{}", session_, eval), progress, cancel);
  out.run_id = s.run_id;
  if (s.ended_early) out.ended_early = s.end_reason.empty() ? "the run ended early" : s.end_reason;
  // Over exactly settle..settle+window: the settle left out.
  out.metrics = console_.runs().metrics(s.run_id, o_.settle_s, o_.window_s);
  return out;
}

void LiveEvaluator::scored(const TuneEvaluation& e, const std::string& objective) {
  if (e.run_id <= 0) return;
  const bool ok = e.failed.empty();
  TuneEvalRow row;
  row.run_id = e.run_id;
  row.session_id = session_;
  row.eval = e.eval;
  if (ok) row.objective = e.objective;
  row.failed = e.failed;
  row.point = e.point;
  log_->add(row);
  console_.recorder().set_notes(
      e.run_id, ok ? fmt::format("tuning session {}, evaluation {}: {} = {:.6g}", session_, e.eval, objective, e.objective)
                   : fmt::format("tuning session {}, evaluation {}: failed: {}", session_, e.eval, e.failed));
}

// The best set goes to a file through `params save`, which writes what is
// in force: so it is put in force first, and the old values back after
// unless asked to keep it.
std::string LiveEvaluator::keep(TuneResult& r, const std::vector<SearchSpace::Write>& original) {
  try {
    if (r.have_best) {
      put_in_force(console_, r.best_values);
      r.saved_to = o_.save.empty() ? fmt::format("tune-{}.params", session_) : o_.save;
      console_.params().save(r.saved_to);
      r.applied = o_.apply;
    }
    if (!r.applied) put_in_force(console_, original);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

void LiveEvaluator::finish(const TuneResult& r) {
  try {
    if (log_) log_->finish(session_, r.end_reason, r.best_run);
  } catch (const std::exception&) {
    // The runs themselves are recorded; only the session's end is missing.
  }
}

std::vector<std::string> LiveEvaluator::kept_words(const TuneResult& r) {
  return {fmt::format("best set saved to {} (params load {} puts it in force); {}", r.saved_to, r.saved_to,
                      r.applied ? "it is in force now (apply)" : "the parameters are back as they were")};
}

std::string LiveEvaluator::nothing_kept_words() const {
  return "no evaluation succeeded: nothing saved; the parameters are back as they were";
}

}  // namespace nlsoft::console
