#include "app/tune/tuner.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <nlopt.hpp>

#include "host/files/cli_error.hpp"
#include "app/link/device.hpp"
#include "app/live/interrupt.hpp"
#include "app/live/live_console.hpp"
#include "app/live/param_text.hpp"
#include "app/live/reference_spec.hpp"
#include "app/text/tokenize.hpp"
#include "app/tune/live_evaluator.hpp"
#include "app/tune/motion_check.hpp"
#include "app/tune/objective.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Why the loop stops early; NLopt only learns that it must.
enum class Stop { None, Budget, Interrupted, Cancelled, Time, Error };

std::string algorithm_name(const std::string& method) {
  return method == "neldermead" ? "NLopt LN_NELDERMEAD (Nelder-Mead)" : "NLopt LN_BOBYQA";
}

std::string values_text(const std::vector<SearchSpace::Write>& writes) {
  std::string s;
  for (const auto& [info, values] : writes)
    s += fmt::format("{}{} = {}", s.empty() ? "" : ", ", info.name, format_param_values(info, values));
  return s;
}

}  // namespace

RefParams tune_reference(LiveConsole& console, const std::string& text) {
  // "swirl hold=1": a preset and its overrides, as `ref` takes them.
  const std::vector<std::string> words = text::tokenize(text);
  if (words.empty()) throw CliError("reference \"\": give a preset, e.g. reference=\"swirl hold=1\"");
  std::vector<std::pair<std::string, std::string>> keys;
  for (size_t i = 1; i < words.size(); ++i) {
    const size_t eq = words[i].find('=');
    if (eq == std::string::npos || eq == 0)
      throw CliError(fmt::format("reference \"{}\": '{}' is not key=value", text, words[i]));
    keys.emplace_back(words[i].substr(0, eq), words[i].substr(eq + 1));
  }
  return reference_from_spec(console.rig(), console.device().info().loop_rate_hz, words[0], keys);
}

namespace {

using Clock = std::chrono::steady_clock;

// One session's state across its evaluations: NLopt calls evaluate() for
// each point it proposes, and what a point did (its run, its score, the
// best so far, why the loop must stop) is kept here between the calls.
class TuningSession {
 public:
  TuningSession(TuneEvaluator& evaluator, const TuneOptions& o, const TuneCallbacks& cb,
                const std::atomic<bool>* cancel, const Objective& objective, SearchSpace& space)
      : ev_(evaluator), o_(o), cb_(cb), cancel_(cancel), objective_(objective), space_(space) {}

  TuneResult run();

 private:
  void out(const std::string& s) const {
    if (cb_.out) cb_.out(s);
  }
  std::string budget_suffix() const { return o_.budget_runs > 0 ? fmt::format("/{}", o_.budget_runs) : ""; }
  void announce();
  void check_stop();
  double evaluate(const std::vector<double>& x);
  void run_point(TuneEvaluation& e, const std::vector<double>& x, RunMetrics& m);
  void judge(TuneEvaluation& e, const TuneOutcome& o);
  void record(TuneEvaluation& e, const std::vector<double>& x, const RunMetrics& m);
  nlopt::result search();
  std::string end_reason(nlopt::result result) const;
  void report(const std::string& finish_error);

  TuneEvaluator& ev_;
  const TuneOptions& o_;
  const TuneCallbacks& cb_;
  const std::atomic<bool>* cancel_;
  const Objective& objective_;
  SearchSpace& space_;
  TuneResult r_;
  Clock::time_point started_;
  // What "the reference barely moves" is measured against.
  std::vector<double> task_;
  bool motion_checked_ = false;
  Stop stop_ = Stop::None;
  std::exception_ptr error_;
  double worst_ok_ = -std::numeric_limits<double>::infinity();
  int eval_ = 0;
};

void TuningSession::announce() {
  out(fmt::format("{}: minimise {} over {} with {}", ev_.name(), objective_.text(), space_.text(),
                  algorithm_name(o_.method)));
  out(ev_.evaluation_words(o_));
  std::string budget;
  if (o_.budget_runs > 0) budget = fmt::format("{} run{}", o_.budget_runs, o_.budget_runs == 1 ? "" : "s");
  if (o_.budget_s > 0) budget += fmt::format("{}{:g} s", budget.empty() ? "" : " or ", o_.budget_s);
  out(fmt::format("budget {}; start {}; Ctrl-C stops and keeps the best", budget, space_.describe(space_.start())));
  for (const std::string& c : space_.clamped()) out("  " + c);
}

// Before each run: cancelled, Ctrl-C, or a budget used up ends the search.
void TuningSession::check_stop() {
  if (cancel_ && cancel_->load()) stop_ = Stop::Cancelled;
  else if (interrupted()) stop_ = Stop::Interrupted;
  else if (o_.budget_s > 0 && std::chrono::duration<double>(Clock::now() - started_).count() >= o_.budget_s)
    stop_ = Stop::Time;
  else if (o_.budget_runs > 0 && eval_ >= o_.budget_runs)
    stop_ = Stop::Budget;
  if (stop_ != Stop::None) throw nlopt::forced_stop();
}

double TuningSession::evaluate(const std::vector<double>& x) {
  check_stop();
  TuneEvaluation e;
  e.eval = ++eval_;
  e.budget = o_.budget_runs;
  e.point = space_.describe(x);
  e.objective = kNaN;
  RunMetrics m;
  try {
    run_point(e, x, m);
  } catch (const nlopt::forced_stop&) {
    throw;
  } catch (const CliError&) {
    if (interrupted()) {
      stop_ = Stop::Interrupted;  // the run was stopped and kept; not scored
    } else {
      stop_ = Stop::Error;
      error_ = std::current_exception();
    }
    throw nlopt::forced_stop();
  } catch (...) {
    stop_ = Stop::Error;
    error_ = std::current_exception();
    throw nlopt::forced_stop();
  }
  record(e, x, m);
  // A failure scores worse than anything seen, yet finite and near the
  // scale of real values: NLopt's models extrapolate from it.
  return e.failed.empty() ? e.objective : (std::isfinite(worst_ok_) ? std::fabs(worst_ok_) * 4 + 1e-3 : 1e3);
}

// The point in force, its run, and the run's score or why it failed.
void TuningSession::run_point(TuneEvaluation& e, const std::vector<double>& x, RunMetrics& m) {
  const TuneOutcome o = ev_.evaluate(
      space_.writes(x), e.eval,
      [&](size_t d, size_t t) {
        if (cb_.progress) cb_.progress(fmt::format("eval {}{}", e.eval, budget_suffix()), d, t);
      },
      cancel_);
  e.run_id = o.run_id;
  if (!o.refused.empty()) {
    // The firmware's cross-parameter rules: the point is outside the
    // feasible set, which is a result, not an error.
    e.failed = "the firmware refused it: " + o.refused;
    return;
  }
  if (cancel_ && cancel_->load()) {
    stop_ = Stop::Cancelled;
    throw nlopt::forced_stop();
  }
  m = o.metrics;
  e.nrmse = metric_value(m, "nrmse").value_or(kNaN);
  if (!motion_checked_ && m.samples > 0) {
    motion_checked_ = true;
    if (const std::string w = still_reference_warning(m, task_, o_.settle_s, o_.window_s); !w.empty()) {
      r_.warnings.push_back(w);
      out(w);
    }
  }
  judge(e, o);
}

void TuningSession::judge(TuneEvaluation& e, const TuneOutcome& o) {
  const RunMetrics& m = o.metrics;
  const double sat = std::isfinite(m.u_saturated) ? m.u_saturated : 0.0;
  if (!o.ended_early.empty()) e.failed = o.ended_early;
  else if (m.lost_frames > 0) e.failed = fmt::format("{} telemetry frame{} lost", m.lost_frames, m.lost_frames == 1 ? "" : "s");
  else if (sat > o_.max_saturated)
    e.failed = fmt::format("u at a limit {:.0f} % of the actuator-time (more than {:.0f} %)", 100 * sat,
                           100 * o_.max_saturated);
  else if (const double v = objective_(m); std::isfinite(v)) e.objective = v;
  else e.failed = "the objective is not defined for this run (a metric it reads is missing)";
}

// The evaluation counted, the best kept, the run's row and notes written,
// and the line printed.
void TuningSession::record(TuneEvaluation& e, const std::vector<double>& x, const RunMetrics& m) {
  const bool ok = e.failed.empty();
  if (ok) {
    worst_ok_ = std::max(worst_ok_, e.objective);
    if (e.eval == 1) r_.start_objective = e.objective;
    if (!r_.have_best || e.objective < r_.best_objective) {
      r_.have_best = true;
      r_.best_objective = e.objective;
      r_.best_eval = e.eval;
      r_.best_run = e.run_id;
      r_.best_point = e.point;
      r_.best_values = space_.writes(x);
      r_.best_metrics = m;
    }
  } else {
    ++r_.failures;
  }
  r_.evaluations = e.eval;
  e.best = r_.have_best ? r_.best_objective : kNaN;
  e.best_eval = r_.best_eval;
  ev_.scored(e, objective_.text());
  out(fmt::format("eval {}{}: {} -> {}  | best {} (eval {})", e.eval, budget_suffix(), e.point,
                  ok ? fmt::format("{:.5g} (nrmse {:.4f})", e.objective, e.nrmse) : "FAILED: " + e.failed,
                  r_.have_best ? fmt::format("{:.5g}", r_.best_objective) : "-", r_.best_eval));
  if (cb_.evaluated) cb_.evaluated(e);
}

nlopt::result TuningSession::search() {
  const size_t dim = space_.size();
  nlopt::opt opt(o_.method == "neldermead" ? nlopt::LN_NELDERMEAD : nlopt::LN_BOBYQA, unsigned(dim));
  nlopt::srand(o_.seed);
  opt.set_lower_bounds(std::vector<double>(dim, 0.0));
  opt.set_upper_bounds(std::vector<double>(dim, 1.0));
  // The budget counts runs, which evaluate() does: NLopt's own count
  // includes the repeat of the start it is given for free below.
  // A tenth of a range's width is as fine as run-to-run noise lets one tell
  // points apart; finer steps would spend runs on noise.
  opt.set_xtol_abs(1e-3);
  opt.set_initial_step(0.25);
  std::vector<double> x = space_.start();
  const std::vector<double> x0 = x;
  double f0 = kNaN;
  bool asked_before = false;
  // When the start lies inside, NLopt asks for it first: that run was made.
  auto g = [&](const std::vector<double>& p) {
    const bool repeat = !asked_before && p == x0 && std::isfinite(f0);
    asked_before = true;
    return repeat ? f0 : evaluate(p);
  };
  using Fn = decltype(g);
  opt.set_min_objective(
      [](const std::vector<double>& p, std::vector<double>&, void* data) { return (*static_cast<Fn*>(data))(p); }, &g);
  double fx = 0;
  nlopt::result result = nlopt::FAILURE;
  try {
    f0 = evaluate(x);
    result = opt.optimize(x, fx);
  } catch (const nlopt::forced_stop&) {
    result = nlopt::FORCED_STOP;
  } catch (const nlopt::roundoff_limited&) {
    result = nlopt::ROUNDOFF_LIMITED;
  } catch (const std::exception& e) {
    if (stop_ == Stop::None) {
      stop_ = Stop::Error;
      error_ = std::make_exception_ptr(CliError(std::string("the optimiser failed: ") + e.what()));
    }
  }
  return result;
}

std::string TuningSession::end_reason(nlopt::result result) const {
  switch (stop_) {
    case Stop::Budget: return fmt::format("budget of {} run{} used", o_.budget_runs, o_.budget_runs == 1 ? "" : "s");
    case Stop::Interrupted: return "interrupted (Ctrl-C)";
    case Stop::Cancelled: return "cancelled";
    case Stop::Time: return fmt::format("time budget of {:g} s used", o_.budget_s);
    case Stop::Error: return "error";
    case Stop::None: break;
  }
  return result == nlopt::XTOL_REACHED || result == nlopt::SUCCESS || result == nlopt::FTOL_REACHED ||
                 result == nlopt::ROUNDOFF_LIMITED
             ? "converged (NLopt's steps fell below a thousandth of each range)"
             : fmt::format("the optimiser stopped (NLopt result {})", int(result));
}

void TuningSession::report(const std::string& finish_error) {
  out(fmt::format("{} ended: {}; {} evaluation{} ({} failed) in {:.1f} s", ev_.name(), r_.end_reason, r_.evaluations,
                  r_.evaluations == 1 ? "" : "s", r_.failures, r_.wall_s));
  if (!r_.have_best) {
    out(ev_.nothing_kept_words());
    return;
  }
  const TrackingMetrics& t = r_.best_metrics.has_true ? r_.best_metrics.truth : r_.best_metrics.predicted;
  out(fmt::format("best: {} = {:.6g} at evaluation {} ({}nrmse {:.4f}{}): {}", objective_.text(), r_.best_objective,
                  r_.best_eval, r_.best_run > 0 ? fmt::format("run {}; ", r_.best_run) : "", t.nrmse,
                  std::isfinite(r_.start_objective) ? fmt::format(", start {:.6g}", r_.start_objective) : "",
                  values_text(r_.best_values)));
  if (!r_.best_metrics.has_true && r_.best_metrics.samples > 0) out(fmt::format("  {}", kNoMeasuredOutput));
  if (!r_.saved_to.empty() && finish_error.empty())
    for (const std::string& line : ev_.kept_words(r_)) out(line);
}

TuneResult TuningSession::run() {
  r_.start_objective = kNaN;
  r_.session = ev_.begin(objective_.text(), space_.text(), o_.method);
  started_ = Clock::now();
  announce();
  task_ = ev_.task_space();
  const nlopt::result result = search();
  r_.wall_s = std::chrono::duration<double>(Clock::now() - started_).count();
  r_.end_reason = end_reason(result);
  const std::string finish_error = ev_.keep(r_, space_.original());
  ev_.finish(r_);
  report(finish_error);
  if (error_) std::rethrow_exception(error_);
  if (!finish_error.empty()) throw CliError("after tuning: " + finish_error);
  return r_;
}

}  // namespace

TuneResult run_tuning(TuneEvaluator& evaluator, const TuneOptions& o, const TuneCallbacks& cb,
                      const std::atomic<bool>* cancel) {
  try {
    validate(o);
  } catch (const std::invalid_argument& e) {
    throw CliError(e.what());
  }
  const Objective objective(o.objective);
  SearchSpace space(evaluator.params(), o.dims);
  return TuningSession(evaluator, o, cb, cancel, objective, space).run();
}

TuneResult run_tuning(LiveConsole& console, const TuneOptions& o, const TuneCallbacks& cb,
                      const std::atomic<bool>* cancel) {
  try {
    validate(o);
  } catch (const std::invalid_argument& e) {
    throw CliError(e.what());
  }
  LiveEvaluator evaluator(console, o);
  // Every name and range checked before the reference changes.
  const Objective objective(o.objective);
  SearchSpace space(evaluator.params(), o.dims);
  if (!o.reference.empty()) console.references().select(tune_reference(console, o.reference));
  return TuningSession(evaluator, o, cb, cancel, objective, space).run();
}

}  // namespace nlsoft::console
