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
#include "app/record/tune_log.hpp"
#include "app/text/tokenize.hpp"
#include "app/tune/motion_check.hpp"
#include "app/tune/objective.hpp"

namespace nlsoft::console {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Why the loop stops early; NLopt only learns that it must.
enum class Stop { None, Budget, Interrupted, Cancelled, Time, Error };

std::string algorithm_name(const std::string& method) {
  return method == "neldermead" ? "NLopt LN_NELDERMEAD (Nelder-Mead)" : "NLopt LN_BOBYQA";
}

void put_in_force(LiveConsole& console, const std::vector<SearchSpace::Write>& writes) {
  for (const auto& [info, values] : writes) console.params().apply(info, values);
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

TuneResult run_tuning(LiveConsole& console, const TuneOptions& o, const TuneCallbacks& cb,
                      const std::atomic<bool>* cancel) {
  using clock = std::chrono::steady_clock;
  auto out = [&](const std::string& s) {
    if (cb.out) cb.out(s);
  };
  try {
    validate(o);
  } catch (const std::invalid_argument& e) {
    throw CliError(e.what());
  }
  const Objective objective(o.objective);
  SearchSpace space(console, o.dims);
  if (!o.reference.empty()) console.references().select(tune_reference(console, o.reference));

  TuneLog log(console.db_path());
  TuneResult r;
  r.start_objective = kNaN;
  r.session = log.begin(objective.text(), space.text(), o.method);
  const auto started = clock::now();
  const size_t dim = space.size();
  out(fmt::format("tuning session {}: minimise {} over {} with {}", r.session, objective.text(), space.text(),
                  algorithm_name(o.method)));
  out(fmt::format("each evaluation is a recorded run: the reference from its first point, {:g} s to settle, measured "
                  "over {:g} s; failed if the watchdog trips, a frame is lost or the inputs sit at a limit over {:g} % of it",
                  o.settle_s, o.window_s, 100 * o.max_saturated));
  std::string budget;
  if (o.budget_runs > 0) budget = fmt::format("{} run{}", o.budget_runs, o.budget_runs == 1 ? "" : "s");
  if (o.budget_s > 0) budget += fmt::format("{}{:g} s", budget.empty() ? "" : " or ", o.budget_s);
  out(fmt::format("budget {}; start {}; Ctrl-C stops and keeps the best", budget, space.describe(space.start())));
  for (const std::string& c : space.clamped()) out("  " + c);

  // The rig's task space (each output's span): what "the reference barely
  // moves" is measured against; the console's rig, shipped or a rig file.
  std::vector<double> task;
  for (const RigOutput& output : console.rig().outputs) task.push_back(output.span);
  bool motion_checked = false;
  Stop stop = Stop::None;
  std::exception_ptr error;
  double worst_ok = -std::numeric_limits<double>::infinity();
  int eval = 0;
  auto f = [&](const std::vector<double>& x) -> double {
    if (cancel && cancel->load()) stop = Stop::Cancelled;
    else if (interrupted()) stop = Stop::Interrupted;
    else if (o.budget_s > 0 && std::chrono::duration<double>(clock::now() - started).count() >= o.budget_s)
      stop = Stop::Time;
    else if (o.budget_runs > 0 && eval >= o.budget_runs)
      stop = Stop::Budget;
    if (stop != Stop::None) throw nlopt::forced_stop();
    TuneEvaluation e;
    e.eval = ++eval;
    e.budget = o.budget_runs;
    e.point = space.describe(x);
    e.objective = kNaN;
    RunMetrics m;
    try {
      try {
        put_in_force(console, space.writes(x));
      } catch (const NackError& refused) {
        // The firmware's cross-parameter rules: the point is outside the
        // feasible set, which is a result, not an error.
        e.failed = std::string("the firmware refused it: ") + refused.what();
      }
      if (e.failed.empty()) {
        const RunSummary s = console.runs().run_for(
            o.settle_s + o.window_s, fmt::format("tune {} #{}", r.session, e.eval),
            [&](size_t d, size_t t) {
              if (cb.progress) cb.progress(fmt::format("eval {}{}", e.eval, o.budget_runs > 0 ? fmt::format("/{}", o.budget_runs) : ""), d, t);
            },
            cancel);
        e.run_id = s.run_id;
        if (cancel && cancel->load()) {
          stop = Stop::Cancelled;
          throw nlopt::forced_stop();
        }
        // Over exactly settle..settle+window: a fast simulator runs past the
        // end before the run is stopped, by a different amount each time.
        m = console.runs().metrics(s.run_id, o.settle_s, o.window_s);
        e.nrmse = metric_value(m, "nrmse").value_or(kNaN);
        if (!motion_checked && m.samples > 0) {
          motion_checked = true;
          if (const std::string w = still_reference_warning(m, task, o.settle_s, o.window_s); !w.empty()) {
            r.warnings.push_back(w);
            out(w);
          }
        }
        const double sat = std::isfinite(m.u_saturated) ? m.u_saturated : 0.0;
        if (s.ended_early) e.failed = s.end_reason;
        else if (m.lost_frames > 0) e.failed = fmt::format("{} telemetry frame{} lost", m.lost_frames, m.lost_frames == 1 ? "" : "s");
        else if (sat > o.max_saturated)
          e.failed = fmt::format("u at a limit {:.0f} % of the actuator-time (more than {:.0f} %)", 100 * sat,
                                 100 * o.max_saturated);
        else if (const double v = objective(m); std::isfinite(v)) e.objective = v;
        else e.failed = "the objective is not defined for this run (a metric it reads is missing)";
      }
    } catch (const nlopt::forced_stop&) {
      throw;
    } catch (const CliError&) {
      if (interrupted()) {
        stop = Stop::Interrupted;  // the run was stopped and kept; not scored
      } else {
        stop = Stop::Error;
        error = std::current_exception();
      }
      throw nlopt::forced_stop();
    } catch (...) {
      stop = Stop::Error;
      error = std::current_exception();
      throw nlopt::forced_stop();
    }
    const bool ok = e.failed.empty();
    if (ok) {
      worst_ok = std::max(worst_ok, e.objective);
      if (e.eval == 1) r.start_objective = e.objective;
      if (!r.have_best || e.objective < r.best_objective) {
        r.have_best = true;
        r.best_objective = e.objective;
        r.best_eval = e.eval;
        r.best_run = e.run_id;
        r.best_point = e.point;
        r.best_values = space.writes(x);
        r.best_metrics = m;
      }
    } else {
      ++r.failures;
    }
    r.evaluations = e.eval;
    e.best = r.have_best ? r.best_objective : kNaN;
    e.best_eval = r.best_eval;
    if (e.run_id > 0) {
      TuneEvalRow row;
      row.run_id = e.run_id;
      row.session_id = r.session;
      row.eval = e.eval;
      if (ok) row.objective = e.objective;
      row.failed = e.failed;
      row.point = e.point;
      log.add(row);
      console.recorder().set_notes(
          e.run_id, ok ? fmt::format("tuning session {}, evaluation {}: {} = {:.6g}", r.session, e.eval, objective.text(), e.objective)
                       : fmt::format("tuning session {}, evaluation {}: failed: {}", r.session, e.eval, e.failed));
    }
    out(fmt::format("eval {}{}: {} -> {}  | best {} (eval {})", e.eval,
                    o.budget_runs > 0 ? fmt::format("/{}", o.budget_runs) : "", e.point,
                    ok ? fmt::format("{:.5g} (nrmse {:.4f})", e.objective, e.nrmse) : "FAILED: " + e.failed,
                    r.have_best ? fmt::format("{:.5g}", r.best_objective) : "-", r.best_eval));
    if (cb.evaluated) cb.evaluated(e);
    // A failure scores worse than anything seen, yet finite and near the
    // scale of real values: NLopt's models extrapolate from it.
    return ok ? e.objective : (std::isfinite(worst_ok) ? std::fabs(worst_ok) * 4 + 1e-3 : 1e3);
  };

  nlopt::opt opt(o.method == "neldermead" ? nlopt::LN_NELDERMEAD : nlopt::LN_BOBYQA, unsigned(dim));
  nlopt::srand(o.seed);
  opt.set_lower_bounds(std::vector<double>(dim, 0.0));
  opt.set_upper_bounds(std::vector<double>(dim, 1.0));
  // The budget counts runs, which f() does: NLopt's own count includes the
  // repeat of the start it is given for free below.
  // A tenth of a range's width is as fine as run-to-run noise lets one tell
  // points apart; finer steps would spend runs on noise.
  opt.set_xtol_abs(1e-3);
  opt.set_initial_step(0.25);
  std::vector<double> x = space.start();
  const std::vector<double> x0 = x;
  double f0 = kNaN;
  bool asked_before = false;
  // When the start lies inside, NLopt asks for it first: that run was made.
  auto g = [&](const std::vector<double>& p) {
    const bool repeat = !asked_before && p == x0 && std::isfinite(f0);
    asked_before = true;
    return repeat ? f0 : f(p);
  };
  using Fn = decltype(g);
  opt.set_min_objective(
      [](const std::vector<double>& p, std::vector<double>&, void* data) { return (*static_cast<Fn*>(data))(p); }, &g);
  double fx = 0;
  nlopt::result result = nlopt::FAILURE;
  try {
    f0 = f(x);
    result = opt.optimize(x, fx);
  } catch (const nlopt::forced_stop&) {
    result = nlopt::FORCED_STOP;
  } catch (const nlopt::roundoff_limited&) {
    result = nlopt::ROUNDOFF_LIMITED;
  } catch (const std::exception& e) {
    if (stop == Stop::None) {
      stop = Stop::Error;
      error = std::make_exception_ptr(CliError(std::string("the optimiser failed: ") + e.what()));
    }
  }
  r.wall_s = std::chrono::duration<double>(clock::now() - started).count();
  switch (stop) {
    case Stop::Budget:
      r.end_reason = fmt::format("budget of {} run{} used", o.budget_runs, o.budget_runs == 1 ? "" : "s");
      break;
    case Stop::Interrupted: r.end_reason = "interrupted (Ctrl-C)"; break;
    case Stop::Cancelled: r.end_reason = "cancelled"; break;
    case Stop::Time: r.end_reason = fmt::format("time budget of {:g} s used", o.budget_s); break;
    case Stop::Error: r.end_reason = "error"; break;
    case Stop::None:
      r.end_reason = result == nlopt::XTOL_REACHED || result == nlopt::SUCCESS || result == nlopt::FTOL_REACHED ||
                             result == nlopt::ROUNDOFF_LIMITED
                         ? "converged (NLopt's steps fell below a thousandth of each range)"
                         : fmt::format("the optimiser stopped (NLopt result {})", int(result));
  }

  // The best set goes to a file through `params save`, which writes what is
  // in force: so it is put in force first, and the old values back after
  // unless asked to keep it.
  std::string finish_error;
  try {
    if (r.have_best) {
      put_in_force(console, r.best_values);
      r.saved_to = o.save.empty() ? fmt::format("tune-{}.params", r.session) : o.save;
      console.params().save(r.saved_to);
      r.applied = o.apply;
    }
    if (!r.applied) put_in_force(console, space.original());
  } catch (const std::exception& e) {
    finish_error = e.what();
  }
  try {
    log.finish(r.session, r.end_reason, r.best_run);
  } catch (const std::exception&) {
    // The runs themselves are recorded; only the session's end is missing.
  }
  out(fmt::format("tuning session {} ended: {}; {} evaluation{} ({} failed) in {:.1f} s", r.session, r.end_reason,
                  r.evaluations, r.evaluations == 1 ? "" : "s", r.failures, r.wall_s));
  if (r.have_best) {
    const TrackingMetrics& t = r.best_metrics.has_true ? r.best_metrics.truth : r.best_metrics.predicted;
    out(fmt::format("best: {} = {:.6g} at evaluation {} (run {}; nrmse {:.4f}{}): {}", objective.text(), r.best_objective,
                    r.best_eval, r.best_run, t.nrmse,
                    std::isfinite(r.start_objective) ? fmt::format(", start {:.6g}", r.start_objective) : "",
                    values_text(r.best_values)));
    if (!r.best_metrics.has_true && r.best_metrics.samples > 0) out(fmt::format("  {}", kNoMeasuredOutput));
    if (!r.saved_to.empty() && finish_error.empty())
      out(fmt::format("best set saved to {} (params load {} puts it in force); {}", r.saved_to, r.saved_to,
                      r.applied ? "it is in force now (apply)" : "the parameters are back as they were"));
  } else {
    out("no evaluation succeeded: nothing saved; the parameters are back as they were");
  }
  if (error) std::rethrow_exception(error);
  if (!finish_error.empty()) throw CliError("after tuning: " + finish_error);
  return r;
}

}  // namespace nlsoft::console
