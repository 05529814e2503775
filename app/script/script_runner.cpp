#include "app/script/script_runner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <thread>

#include "host/files/cli_error.hpp"
#include "app/link/device_check.hpp"
#include "app/link/link_error.hpp"
#include "host/files/printable.hpp"
#include "app/live/interrupt.hpp"
#include "app/live/param_text.hpp"
#include "app/live/ident_plan.hpp"
#include "app/live/reference_spec.hpp"
#include "app/model/model_size_words.hpp"
#include "app/record/csv_export.hpp"
#include "app/record/loop_rate.hpp"
#include "app/record/merge_y.hpp"
#include "app/record/run_store.hpp"
#include "app/replay/replay_source.hpp"
#include "app/script/ident_words.hpp"
#include "app/tune/replay_evaluator.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

using host::CliError;
using host::RigOutput;
using host::printable;
using host::reference_kind_name;

namespace {

std::string summary_line(const RunSummary& s, bool ident = false) {
  const RunMetrics& m = s.metrics;
  const TrackingMetrics& t = m.has_true ? m.truth : m.predicted;
  std::string rmse;
  for (double r : t.rmse) rmse += (rmse.empty() ? "" : " ") + fmt::format("{:.4g}", r);
  return fmt::format("run {}{}: {} samples, {:.2f} s, rmse [{}] nrmse {} max_error {:.4g}, {}, "
                     "compute p50 {:.1f} us p99 {:.1f} us, lost {}{}",
                     s.run_id, s.label.empty() ? "" : " (" + printable(s.label) + ")", m.samples, m.duration_s, rmse, nrmse_words(t.nrmse),
                     t.max_error, loop_rate_text(m), m.compute_p50_us, m.compute_p99_us, m.lost_frames,
                     s.end_reason == "completed" ? "" : ", " + s.end_reason) +
         (m.has_true || m.samples == 0 ? "" : ident ? "; no measured output (y_true)" : std::string("; ") + kNoMeasuredOutput);
}

// What `run 1s` meant: control steps at the loop rate, the firmware's time,
// not wall time, which a --sim-fast simulator runs far faster than the
// clock (the steps it makes before RUN_STOP reaches it are not recorded:
// ActiveRun::planned_steps). A sample is `decimation` steps.
std::string timed_run_words(double asked_s, double rate_hz, int decimation, const RunMetrics& m) {
  if (!(rate_hz > 0)) return "";
  const double target = std::round(asked_s * rate_hz);
  const double steps = double(m.samples) * std::max(decimation, 1);
  std::string s = fmt::format("; {:g} s asked = {:.0f} control steps at {:g} Hz (the firmware's time, not wall time): "
                              "{} samples = {:.2f} s of it",
                              asked_s, target, rate_hz, m.samples, steps / rate_hz);
  if (m.wall_s > 0) s += fmt::format(", in {:.2f} s of wall time", m.wall_s);
  return s;
}

}  // namespace

// A run that ended before its duration measured something else than the
// script asked for: a failure, like a failed expect, unless it said early=ok.
// `ident ... y_from=FILE.csv [y_offset=S]`: the capture merged into the run
// just recorded, as `ident --y-from` does; a capture that cannot be merged
// leaves the run as recorded and says how to merge it later.
void ScriptRunner::merge_capture(int64_t run_id, const Command& c) {
  std::optional<double> offset;
  for (const auto& [k, v] : c.options)
    if (k == "y_offset") offset = std::strtod(v.c_str(), nullptr);
  std::vector<std::string> names;
  try {
    for (const RigOutput& o : console_.rig().outputs) names.push_back(o.name);
  } catch (const CliError&) {
  }
  try {
    out_(merge_words(run_id, c.capture, merge_y(console_.db_path(), run_id, c.capture, offset, names)));
  } catch (const CliError& e) {
    throw CliError(fmt::format("{}; run {} is recorded without the capture (runs merge-y {} {} merges it later)",
                               e.what(), run_id, run_id, c.capture));
  }
}

void ScriptRunner::check_completed(const RunSummary& s, const Command& c, const std::string& file) {
  if (!s.ended_early || c.allow_early) return;
  ++incomplete_runs_;
  out_(fmt::format("{}:{}: run {} did not complete: {} (add early=ok to '{}' if that is expected)", file, c.line,
                   s.run_id, s.end_reason, c.text));
}

int ScriptRunner::run(const Script& script) {
  for (const Command& c : script.commands) {
    if (interrupted()) {
      out_(fmt::format("{}:{}: {} before '{}'", script.file, c.line, interrupt_reason(), c.text));
      if (console_.runs().running()) {
        try {
          const RunSummary s = console_.runs().stop(interrupt_reason());
          out_(fmt::format("run {} stopped and kept ({} samples)", s.run_id, s.metrics.samples));
        } catch (const std::exception& e) {
          out_(fmt::format("error: the run could not be stopped: {}", e.what()));
        }
      }
      return 2;
    }
    try {
      execute(c, script.file);
    } catch (const ScriptError& e) {
      out_(std::string("error: ") + e.what());
      if (console_.runs().running()) {
        try {
          console_.runs().stop("script error");
        } catch (...) {
        }
      }
      return 2;
    }
  }
  return failed_ > 0 || incomplete_runs_ > 0 || fruitless_tunes_ > 0 ? 1 : 0;
}

void ScriptRunner::cancel() {
  {
    std::lock_guard<std::mutex> lock(cancel_mu_);
    cancelled_ = true;
  }
  cancel_cv_.notify_all();
}

void ScriptRunner::throw_if_cancelled(const Command& c, const std::string& file) const {
  if (cancelled_.load()) throw ScriptError(file, c.line, "cancelled: '" + c.text + "'");
}

void ScriptRunner::execute(const Command& c, const std::string& file) {
  using K = Command::Kind;
  throw_if_cancelled(c, file);
  try {
    switch (c.kind) {
      case K::Set: {
        const auto v = console_.params().set(c.name, c.values);
        const ParamInfo info = console_.params().resolve(c.name).first;
        out_(fmt::format("{} = {}", info.name, format_param_named(info, v)));
        break;
      }
      case K::Get: {
        const auto [info, v] = console_.params().get(c.name);
        out_(fmt::format("{} = {}{}", info.name, format_param_named(info, v), info.unit.empty() ? "" : " " + info.unit));
        break;
      }
      case K::ParamsSave:
        console_.params().save(c.name);
        out_(fmt::format("parameters saved to {}", c.name));
        break;
      case K::ParamsLoad: say_changes(console_.params().load(c.name), c.name + ": every parameter already has that value"); break;
      case K::ParamsReapply: say_changes(console_.resets().reapply(), "no edits in this session to send again"); break;
      case K::ParamsDiff:
        say_changes(console_.params().diff_from_defaults(), "every parameter has the value the firmware boots with");
        break;
      case K::ParamsReset:
        say_changes(console_.params().reset_to_defaults(),
                    "every parameter already has the value the firmware boots with");
        break;
      case K::Ref: {
        const RefParams r = reference_from_spec(console_.rig(), console_.device().info().loop_rate_hz, c.name, c.options);
        console_.references().select(r);
        // Its kind first: a line cut to a narrow terminal still names it.
        out_(fmt::format("reference {} in force: {}", reference_kind_name(r.kind), reference_json(r)));
        break;
      }
      case K::RefLoad: ref_load(c); break;
      case K::ModelUpload: model_upload(c); break;
      case K::Run: timed_run(c, file); break;
      case K::Ident: ident(c, file); break;
      case K::Start: out_(fmt::format("run {} started", console_.runs().start(c.label))); break;
      case K::Stop: out_(summary_line(console_.runs().stop())); break;
      case K::Hold: console_.runs().hold(protocol::HoldMode::Hold); out_("holding"); break;
      case K::Neutral: console_.runs().hold(protocol::HoldMode::Neutral); out_("actuators neutral"); break;
      case K::Resume: console_.runs().hold(protocol::HoldMode::Resume); out_("resumed"); break;
      case K::Wait: wait(c.seconds); break;
      case K::Expect: expect(c, file); break;
      case K::ExportCsv: {
        const auto last = console_.runs().last();
        if (!last) throw CliError("export needs a finished run first (run DURATION)");
        RunStore store(console_.db_path());
        const size_t rows = export_run_csv(store, last->run_id, c.name);
        out_(fmt::format("run {}: {} samples written to {}", last->run_id, rows, c.name));
        break;
      }
      case K::Echo: out_(c.name); break;
      case K::Settings: {
        const auto action = c.name == "save"       ? protocol::SettingsAction::Save
                            : c.name == "defaults" ? protocol::SettingsAction::Defaults
                                                   : protocol::SettingsAction::Report;
        out_(console_.device().settings(action));
        break;
      }
      case K::Devices: {
        int bad = 0;
        for (const std::string& line : device_lines(console_.rig(), console_.device().devices(), bad)) out_(line);
        break;
      }
      case K::Note: note(c.name); break;
      case K::Sweep: sweep(c, file); break;
      case K::Tune: tune(c); break;
    }
  } catch (const ScriptError&) {
    throw;
  } catch (const std::exception& e) {
    throw ScriptError(file, c.line, e.what());
  }
}

// The lines a params command changed or found, or `none` when there are none.
void ScriptRunner::say_changes(const std::vector<std::string>& lines, const std::string& none) {
  if (lines.empty()) out_(none);
  for (const auto& l : lines) out_("  " + l);
}

void ScriptRunner::ref_load(const Command& c) {
  uint16_t hold = 1;
  for (const auto& [k, v] : c.options) {
    RefParams tmp{};
    set_reference_key(tmp, console_.device().info().loop_rate_hz, k, v);
    hold = tmp.hold;
  }
  console_.references().upload_table(c.name, hold, [&](size_t d, size_t t) {
    if (progress_) progress_("upload " + c.name, d, t);
  });
  out_(fmt::format("reference table {} uploaded and selected (hold {})", c.name, hold));
}

void ScriptRunner::model_upload(const Command& c) {
  const auto r = console_.model_upload().send(c.name, [&](size_t d, size_t t) {
    if (progress_) progress_("model " + c.name, d, t);
  });
  out_(fmt::format("model {} in force: hash {:08x} confirmed (was {:08x}), {} bytes, {}", c.name, r.hash,
                   r.previous_hash, r.bytes, model_size_words(r.params, r.normalisation)));
}

void ScriptRunner::timed_run(const Command& c, const std::string& file) {
  const RunSummary s = console_.runs().run_for(
      c.seconds, c.label,
      [&](size_t d, size_t t) {
        if (progress_) progress_(fmt::format("run {:g}s", c.seconds), d, t);
      },
      &cancelled_);
  int decimation = 1;
  try {
    decimation = RunStore(console_.db_path()).run(s.run_id).decimation;
  } catch (const std::exception&) {
    // The summary then counts a sample as one step.
  }
  out_(summary_line(s) + timed_run_words(c.seconds, console_.device().info().loop_rate_hz, decimation, s.metrics));
  check_completed(s, c, file);
}

void ScriptRunner::ident(const Command& c, const std::string& file) {
  const protocol::Info info = console_.device().info();
  IdentLine line;
  line.unlimited = console_.link_unlimited();
  line.sensor_health = sends_sensor_health(console_.device());
  const IdentWords w = ident_words(c);
  const IdentPlan plan = plan_ident(w, double(info.loop_rate_hz), info.m, info.n, info.w, line, console_.known_rig());
  out_(plan.excitation_words);
  out_(plan.line_words);
  const RunSummary s = console_.runs().run_ident(
      plan.start, plan.excitation_json,
      c.label.empty() ? fmt::format("ident {} seed {} {}", w.signal, w.seed, w.duration) : c.label,
      [&](size_t d, size_t t) {
        if (progress_) progress_(fmt::format("ident {}", w.signal), d, t);
      });
  out_(fmt::format("{}; identification run: {} of {} steps recorded (decimation {})", summary_line(s, true),
                   s.metrics.samples, plan.start.duration, plan.start.decimation));
  if (!c.capture.empty()) merge_capture(s.run_id, c);
  check_completed(s, c, file);
}

void ScriptRunner::wait(double seconds) {
  // A signal cannot notify the condition variable: look at it every 50 ms.
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
  std::unique_lock<std::mutex> lock(cancel_mu_);
  while (!cancelled_.load() && !interrupted() && std::chrono::steady_clock::now() < until)
    cancel_cv_.wait_until(lock, std::min(until, std::chrono::steady_clock::now() + std::chrono::milliseconds(50)));
}

void ScriptRunner::expect(const Command& c, const std::string& file) {
  const auto last = console_.runs().last();
  if (!last) throw CliError("expect needs a finished run first (run DURATION)");
  const auto v = metric_value(last->metrics, c.name);
  if (!v) throw CliError(fmt::format("metric '{}' is not available for run {}", c.name, last->run_id));
  const uint64_t lost = last->metrics.lost_frames;
  if (lost > 0 && !c.allow_lost && canonical_metric_name(c.name) != "lost_frames" &&
      canonical_metric_name(c.name) != "gaps") {
    ++failed_;
    out_(fmt::format("{}:{}: expect {} {} {:g} failed: run {} lost {} sample{} (on the link, or refused as "
                     "not finite or of another shape), so {} = {:.6g} scores part of it (add lost=ok if that "
                     "is expected)",
                     file, c.line, c.name, cmp_op_text(c.op), c.value, last->run_id, lost, lost == 1 ? "" : "s",
                     c.name, *v));
  } else if (compare(*v, c.op, c.value)) {
    ++passed_;
    out_(fmt::format("ok: {} = {:.6g} {} {:g}", c.name, *v, cmp_op_text(c.op), c.value));
  } else {
    ++failed_;
    out_(fmt::format("{}:{}: expect {} {} {:g} failed: {} = {:.6g} (run {})", file, c.line, c.name,
                     cmp_op_text(c.op), c.value, c.name, *v, last->run_id));
  }
}

// Notes on the run in progress, else on the last one.
void ScriptRunner::note(const std::string& text) {
  const auto last = console_.runs().last();
  const int64_t id = console_.runs().running() ? console_.runs().current() : last ? last->run_id : 0;
  if (id == 0) throw CliError("note needs a run (start one, or after run DURATION)");
  console_.recorder().set_notes(id, text);
  out_(fmt::format("notes on run {}: {}", id, text));
}

// A session where every evaluation failed found nothing: the script fails,
// as for a failed expect.
void ScriptRunner::tune(const Command& c) {
  TuneCallbacks cb;
  cb.out = out_;
  cb.progress = progress_;
  cb.evaluated = tune_observer_;
  TuneOptions o = parse_tune_words(c.values);
  const TuneResult r = o.on_replays() ? tune_on_replays(o, cb) : run_tuning(console_, o, cb, &cancelled_);
  if (!r.have_best && !cancelled_.load()) ++fruitless_tunes_;
}

// `tune replay=N`: the candidates scored on replays of run N in this
// process (as `tune --replay N`), the connected firmware untouched until
// `apply` loads the best set onto it, as `params load` would: tuned on the
// recording, then tried on the rig.
TuneResult ScriptRunner::tune_on_replays(TuneOptions& o, const TuneCallbacks& cb) {
  if (o.replay_last) {
    const auto last = console_.runs().last();
    if (!last) throw CliError("tune replay=last needs a finished run of this session first (run DURATION)");
    o.replay = last->run_id;
  }
  const ReplaySource src = open_replay_source(console_.db_path(), o.replay, console_.rig(), o.model, o.plant);
  fit_window_to_run(src, o);
  ReplayEvaluator evaluator(src, o, console_.recording());
  out_(fmt::format("tune: run {} ({} steps at {:g} Hz) replayed per candidate in this process; the firmware is not "
                   "touched{}",
                   src.id, src.steps(), src.start.row.loop_rate_hz, o.apply ? " until the best is applied" : ""));
  for (const std::string& s : src.start.not_repeated) out_(s);
  TuneResult r = run_tuning(evaluator, o, cb, &cancelled_);
  if (o.apply && r.have_best && !r.saved_to.empty() && !cancelled_.load()) {
    const std::vector<std::string> changed = console_.params().load(r.saved_to);
    r.applied = true;
    out_(fmt::format("tune: the best set ({}) loaded onto the firmware (apply): {}", r.saved_to,
                     changed.empty() ? std::string("nothing differed")
                                     : fmt::format("{}", fmt::join(changed, "; "))));
  }
  return r;
}

void ScriptRunner::sweep(const Command& c, const std::string& file) {
  const auto [info, original] = console_.params().get(c.name);
  std::vector<std::string> header = {c.name, "run", "samples", "rmse", "nrmse", "nrmse_space", "max_error", "lost", "p99_us"};
  std::vector<std::vector<std::string>> rows;
  std::exception_ptr failure;
  for (const std::string& v : c.values) {
    if (cancelled_.load()) break;
    try {
      console_.params().set(c.name, {v});
      // RUN_START restarts the reference from its first point with the
      // actuators neutral, so rows start alike; each runs `settle` longer
      // and is measured without it.
      const RunSummary s = console_.runs().run_for(
          c.settle_s + c.seconds, c.label.empty() ? fmt::format("sweep {}={}", c.name, v) : c.label,
          [&](size_t d, size_t t) {
            if (progress_) progress_(fmt::format("{}={}", c.name, v), d, t);
          },
          &cancelled_);
      // Over exactly the window asked for, the settle left out.
      const RunMetrics measured = console_.runs().metrics(s.run_id, c.settle_s, c.seconds);
      auto f = [&](const char* m) { return fmt::format("{:.5g}", metric_value(measured, m).value_or(0)); };
      rows.push_back({v, std::to_string(s.run_id) + (s.ended_early ? " (ended early)" : ""), f("samples"), f("rmse"), f("nrmse"), f("nrmse_space"),
                      f("max_error"), f("lost_frames"), f("compute_p99_us")});
      check_completed(s, c, file);
    } catch (...) {
      failure = std::current_exception();
      break;
    }
  }
  // Put the parameter back as it was before the sweep.
  try {
    console_.params().apply(info, original);
  } catch (...) {
  }
  std::vector<size_t> w(header.size());
  for (size_t i = 0; i < header.size(); ++i) {
    w[i] = header[i].size();
    for (const auto& r : rows) w[i] = std::max(w[i], r[i].size());
  }
  auto line = [&](const std::vector<std::string>& r) {
    std::string s;
    for (size_t i = 0; i < r.size(); ++i) s += fmt::format("{:>{}}  ", r[i], w[i]);
    out_(s);
  };
  out_(fmt::format("each row: the reference restarted from its first point, actuators from neutral; {}",
                   c.settle_s > 0 ? fmt::format("measured over {:g} s after {:g} s to settle", c.seconds, c.settle_s)
                                  : fmt::format("measured over all {:g} s", c.seconds)));
  line(header);
  for (const auto& r : rows) line(r);
  out_(fmt::format("{} restored to {}", info.name, format_param_values(info, original)));
  if (failure) std::rethrow_exception(failure);
}

}  // namespace nlsoft::console
