#include "app/tune/replay_evaluator.hpp"

#include <fmt/format.h>
#include <stdlib.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

#include "app/link/link_error.hpp"
#include "app/link/param_resolve.hpp"
#include "app/live/params_file.hpp"
#include "app/record/run_metrics.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sqlite.hpp"
#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;
using host::RigOutput;

// The parameters as a replay starts with them: run N's at its start, in
// the simulator's own list (read once, from a replay set up and never run).
class ReplayEvaluator::Params final : public ParamSource {
 public:
  explicit Params(const ReplaySource& src) : probe_(src, kNoiseSeed) {
    for (auto& [info, values] : probe_.params()) values_[info.name] = std::move(values);
  }
  std::pair<ParamInfo, int> resolve(const std::string& name) override { return resolve_param(probe_.catalog(), name); }
  std::vector<double> in_force(const ParamInfo& info) override { return values_.at(info.name); }

 private:
  ReplayRun probe_;
  std::map<std::string, std::vector<double>> values_;
};

namespace {

std::string share_words(double share) {
  return std::isfinite(share) ? fmt::format("{:.1f} %", 100 * share) : "n/a";
}

double nrmse_of(const RunMetrics& m) { return (m.has_true ? m.truth : m.predicted).nrmse; }

RunMetrics metrics_of(const std::string& db, int64_t id, double settle_s, double window_s) {
  try {
    RunStore store(db);
    return run_metrics(store, id, settle_s, window_s);
  } catch (const DbError& e) {
    throw CliError(e.what());
  }
}

}  // namespace

void fit_window_to_run(const ReplaySource& src, TuneOptions& o) {
  const double length = src.duration_s();
  if (o.settle_s >= length)
    throw CliError(fmt::format("tune: run {} lasts {:.2f} s; settling {:g} s leaves nothing of it to score", src.id,
                               length, o.settle_s));
  if (!o.window_given) {
    o.window_s = length - o.settle_s;
  } else if (o.settle_s + o.window_s > length + 0.5 / src.start.row.loop_rate_hz) {
    throw CliError(fmt::format("tune: run {} lasts {:.2f} s; settling {:g} s and a window of {:g} s reach past its "
                               "end: give a shorter window, or none to score up to the end",
                               src.id, length, o.settle_s, o.window_s));
  }
}

ReplayEvaluator::ReplayEvaluator(const ReplaySource& src, const TuneOptions& o, bool record_best)
    : src_(src), o_(o), record_best_(record_best), params_(std::make_unique<Params>(src)) {
  // The candidates' replays in a database of their own: the figures of
  // each are read back as any run's are, and none lands in the recording.
  char tmpl[] = "/tmp/nlsoft-tune-replay-XXXXXX";
  if (!::mkdtemp(tmpl)) throw CliError(fmt::format("cannot create a scratch database: {}", std::strerror(errno)));
  scratch_dir_ = tmpl;
  scratch_db_ = scratch_dir_ + "/replays.db";
  try {
    scratch_ = std::make_unique<Recorder>(scratch_db_);
  } catch (const DbError& e) {
    std::error_code ec;
    std::filesystem::remove_all(scratch_dir_, ec);
    throw CliError(e.what());
  }
  recorded_ = metrics_of(src.db, src.id, o.settle_s, o.window_s);
}

ReplayEvaluator::~ReplayEvaluator() {
  scratch_.reset();
  std::error_code ec;
  std::filesystem::remove_all(scratch_dir_, ec);
}

ParamSource& ReplayEvaluator::params() { return *params_; }

std::vector<double> ReplayEvaluator::task_space() const {
  std::vector<double> task;
  for (const RigOutput& output : src_.rig.outputs) task.push_back(output.span);
  return task;
}

int64_t ReplayEvaluator::begin(const std::string&, const std::string&, const std::string&) { return 0; }

std::string ReplayEvaluator::name() const { return fmt::format("tuning on replays of run {}", src_.id); }

std::string ReplayEvaluator::evaluation_words(const TuneOptions& o) const {
  return fmt::format("each evaluation is a replay of run {} in this process (the simulator's firmware and plant "
                     "model, not the rig; not recorded): its reference and parameters at its start, the candidate on "
                     "top, {} steps at {:g} Hz, measured from {:g} s over {:g} s; failed if the inputs sit at a limit "
                     "over {:g} % of it",
                     src_.id, src_.steps(), src_.start.row.loop_rate_hz, o.settle_s, o.window_s, 100 * o.max_saturated);
}

TuneOutcome ReplayEvaluator::replay(const std::vector<SearchSpace::Write>& point, Recorder& recorder,
                                    const std::string& db, const std::string& label, const std::string& notes,
                                    const Progress& progress) {
  TuneOutcome out;
  ReplayRun run(src_, kNoiseSeed);
  try {
    for (const auto& [info, values] : point) run.set(info, values, "");
  } catch (const NackError& refused) {
    // The firmware's cross-parameter rules (Nc <= N, u_min < u_max): the
    // point is outside the feasible set, a result as on a board.
    out.refused = refused.what();
    return out;
  }
  run.prepare();
  out.run_id = recorder.begin_run(run.run_info(label, notes));
  run.record(recorder, out.run_id, progress);
  out.metrics = metrics_of(db, out.run_id, o_.settle_s, o_.window_s);
  return out;
}

TuneOutcome ReplayEvaluator::evaluate(const std::vector<SearchSpace::Write>& point, int eval,
                                      const Progress& progress, const std::atomic<bool>*) {
  // A replay takes a fraction of a second: cancel and Ctrl-C are seen
  // between evaluations. The scratch run is no run of the recording.
  TuneOutcome out = replay(point, *scratch_, scratch_db_, fmt::format("tune --replay {} #{}", src_.id, eval), "",
                           progress);
  out.run_id = 0;
  return out;
}

std::string ReplayEvaluator::keep(TuneResult& r, const std::vector<SearchSpace::Write>&) {
  // Nothing is in force anywhere: the best is saved, and recorded when asked.
  if (!r.have_best) return "";
  try {
    best_ = r.best_metrics;
    if (record_best_) {
      Recorder recorder(src_.db);
      const TuneOutcome o = replay(
          r.best_values, recorder, src_.db,
          fmt::format("tune --replay {}: best (evaluation {})", src_.id, r.best_eval),
          fmt::format("tune --replay {}: the best of {} evaluations, {}; {}", src_.id, r.evaluations, r.best_point,
                      r.end_reason),
          {});
      r.best_run = o.run_id;
      best_ = o.metrics;
    }
    ReplayRun best(src_, kNoiseSeed);
    for (const auto& [info, values] : r.best_values) best.set(info, values, "");
    r.saved_to = o_.save.empty() ? fmt::format("tune-replay-{}.params", src_.id) : o_.save;
    write_params_file(r.saved_to, best.info().info, best.params());
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::vector<std::string> ReplayEvaluator::kept_words(const TuneResult& r) {
  std::vector<std::string> lines;
  lines.push_back(fmt::format("best set saved to {} (params load {} puts it in force on a rig or a simulator)",
                              r.saved_to, r.saved_to));
  lines.push_back(r.best_run > 0 ? fmt::format("the best's replay is recorded as run {} (kind replay); the candidates' "
                                               "replays are not recorded",
                                               r.best_run)
                                 : "nothing recorded (--no-record)");
  const double end = o_.settle_s + o_.window_s;
  lines.push_back(fmt::format("figures from replays on the simulator in this process (its firmware and plant model), "
                              "not from the rig; over {:g} s to {:g} s of the run:",
                              o_.settle_s, end));
  const std::string best = r.best_run > 0 ? fmt::format("best (run {})", r.best_run) : "best";
  lines.push_back(fmt::format("  {:<12} {:>16} {:>16}", "", fmt::format("recorded (run {})", src_.id), best));
  lines.push_back(fmt::format("  {:<12} {:>16.4f} {:>16.4f}", "nrmse", nrmse_of(recorded_), nrmse_of(best_)));
  lines.push_back(fmt::format("  {:<12} {:>16.4g} {:>16.4g}", "u_effort", recorded_.u_effort, best_.u_effort));
  lines.push_back(fmt::format("  {:<12} {:>16} {:>16}", "u_saturated", share_words(recorded_.u_saturated),
                              share_words(best_.u_saturated)));
  return lines;
}

std::string ReplayEvaluator::nothing_kept_words() const {
  return "no evaluation succeeded: nothing saved, nothing recorded";
}

}  // namespace nlsoft::console
