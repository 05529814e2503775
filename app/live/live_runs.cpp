// The run's lifecycle: started (closed loop or identification), held,
// waited out for a duration with every way it can end early, stopped once
// whoever stops it, and its summary.
#include "app/live/live_runs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "host/files/cli_error.hpp"
#include "app/live/ident_plan.hpp"
#include "app/live/interrupt.hpp"
#include "app/live/param_text.hpp"
#include "app/live/reference_spec.hpp"
#include "app/record/loop_rate.hpp"
#include "app/record/run_edit.hpp"
#include "app/record/run_store.hpp"

namespace nlsoft::console {

using host::CliError;

namespace p = nlsoft::protocol;

int64_t LiveRuns::start(const std::string& label) { return begin(label, nullptr, "", 0); }

int64_t LiveRuns::begin(const std::string& label, p::IdentStart* ident, const std::string& excitation_json,
                        uint64_t planned_steps) {
  ActiveRun& run = p_.run;
  if (running()) throw CliError(fmt::format("run {} is already active; stop it first", current()));
  if (const std::string err = run.recorder.error(); !err.empty()) throw CliError("recording has stopped: " + err);
  check_label(label);
  const p::Info info = p_.device.info();
  RunInfo ri;
  ri.label = label;
  ri.platform = p_.device.rig_label();
  ri.firmware = fmt::format("{} {}.{}.{}", info.firmware, info.fw_major, info.fw_minor, info.fw_patch);
  ri.model_hash = info.model_hash;
  ri.param_hash = info.param_hash;
  ri.loop_rate_hz = info.loop_rate_hz;
  ri.n = info.n;
  ri.m = info.m;
  run.decimation = ident ? std::max<uint16_t>(ident->decimation, 1) : run.telemetry_decimation.load();
  ri.decimation = run.decimation.load();
  if (ident) {
    // Open loop: no reference is followed.
    ri.kind = "ident";
    ri.w = info.w;
    ri.excitation = excitation_json;
  } else {
    ri.reference = p_.references.run_json();
    // Its samples carry the sensors (SENSOR_SAMPLE), what a model reads.
    ri.w = run.sensors_w.load();
  }
  for (const auto& [pi, v] : p_.device.get_all()) ri.params.emplace_back(pi.name, format_param_values(pi, v));
  const int64_t id = run.recorder.begin_run(ri);
  run.k = 0;
  run.lost = 0;
  run.have_last_step = false;
  run.user_hold = false;
  run.left_state = 0;
  run.left_watchdog = 0;
  run.resync_after_gap = false;
  run.step_went_back = false;
  run.planned_steps = planned_steps;
  run.label = label;
  run.started_ns = std::chrono::steady_clock::now().time_since_epoch().count();
  p_.live.clear();
  run.id = id;
  try {
    if (ident) {
      ident->run_id = uint32_t(id);
      p_.device.ident_start(*ident);
    } else {
      p_.device.run_start(uint32_t(id));
    }
  } catch (const std::exception& e) {
    run.id = 0;
    run.decimation = run.telemetry_decimation.load();
    run.recorder.end_run(id, std::string("not started: ") + e.what(), 0, 0);
    if (const auto* nack = dynamic_cast<const NackError*>(&e); ident && nack)
      throw CliError(fmt::format("the firmware refused the identification run: {}", e.what()));
    // WRONG_STATE on field 0 (run_id): another run is active; on no field:
    // the firmware has no model to run (firmware.hpp run_start).
    if (const auto* nack = dynamic_cast<const NackError*>(&e); nack && nack->status() == p::StatusCode::WrongState)
      throw CliError(nack->nack.field == p::kNoField
                         ? "the firmware has no model to run: upload one first (model upload FILE.nlsm)"
                         : "the firmware is already running another run; stop it first");
    throw;
  }
  p_.session.take_longest_write_gap();  // the run's own silences from here
  {
    std::lock_guard<std::mutex> lock(mu_);
    session_runs_.push_back(id);
  }
  return id;
}

RunSummary LiveRuns::stop(const std::string& reason) {
  std::lock_guard<std::mutex> stopping(stop_mu_);
  const int64_t id = current();
  if (id == 0) throw CliError("no run is active");
  return stop_locked(id, reason);
}

RunSummary LiveRuns::finish(int64_t id, const std::string& label, const std::string& reason) {
  std::lock_guard<std::mutex> stopping(stop_mu_);
  if (current() == id) return stop_locked(id, reason);
  // Someone else stopped it; their stop finished under stop_mu_.
  std::lock_guard<std::mutex> lock(mu_);
  if (last_run_ && last_run_->run_id == id) return *last_run_;
  RunSummary s;
  s.run_id = id;
  s.label = label;
  s.end_reason = "stopped";
  return s;
}

RunSummary LiveRuns::stop_locked(int64_t id, const std::string& reason) {
  ActiveRun& run = p_.run;
  std::string why = reason;
  // A simulator that has ended has nothing to stop: asking it would only
  // time out and bury the reason under "link lost at stop".
  if (p_.simulator.exit_words().empty()) {
    try {
      p_.device.run_stop();
    } catch (const std::exception& e) {
      // Keeps why the run ended (an early end's cause comes first).
      why = reason + "; link lost at stop: " + e.what();
    }
  }
  // Every frame of the run came before RUN_STOP's ACK on the one reader.
  run.id = 0;
  run.decimation = run.telemetry_decimation.load();
  run.recorder.end_run(id, why, run.k.load(), run.lost.load());
  RunSummary s;
  s.run_id = id;
  s.label = run.label;
  s.end_reason = why;
  s.metrics = metrics(id);
  if (const std::string w = loop_rate_warning(s.metrics); !w.empty()) p_.notices.say(fmt::format("run {}: {}", id, w));
  // Samples that arrived and could not be saved (a database locked past
  // --db-busy, a full queue) are in the run's gaps; say so at its end.
  if (const Recorder::Loss loss = run.recorder.loss(id); loss.samples > 0)
    p_.notices.say(fmt::format("run {}: {} of {} samples saved; {} lost: {}", id, s.metrics.samples, run.k.load(), loss.samples,
                    loss.reason));
  std::lock_guard<std::mutex> lock(mu_);
  last_run_ = s;
  return s;
}

void LiveRuns::hold(p::HoldMode mode) {
  ActiveRun& run = p_.run;
  if (!running()) throw CliError("no run is active");
  // Set before a hold is sent and cleared only after a resume is
  // acknowledged, so no STATUS of a held run reads as the firmware leaving it.
  if (mode != p::HoldMode::Resume) run.user_hold = true;
  p_.device.run_hold(mode);
  if (mode == p::HoldMode::Resume) run.user_hold = false;
  run.recorder.add_link_event(run.id.load(), "hold",
                            mode == p::HoldMode::Hold ? "hold" : mode == p::HoldMode::Neutral ? "neutral" : "resume");
}

namespace {

std::string left_run_reason(uint8_t state, uint8_t watchdog, std::chrono::milliseconds console_gap) {
  // STATUS watchdog bit 2: the link went silent during this run.
  constexpr uint8_t kWatchdogTripped = 0x04;
  const char* where = state == uint8_t(p::RunState::Hold)      ? "holding"
                      : state == uint8_t(p::RunState::Neutral) ? "with the actuators neutral"
                      : state == uint8_t(p::RunState::Fault)   ? "in its fault state"
                                                               : "idle";
  // The console's own longest silence beside it: under watchdog_ms, the
  // bytes were written in time and held back on the way (the line, or a
  // host that did not schedule the firmware); the firmware's LOG says how
  // long it heard nothing.
  if (watchdog & kWatchdogTripped)
    return fmt::format("the firmware's link watchdog tripped (nothing from the console for watchdog_ms; the console "
                       "wrote at most {} ms apart during the run); it is {}",
                       console_gap.count(), where);
  return fmt::format("the firmware left the run on its own; it is {}", where);
}

}  // namespace

RunSummary LiveRuns::run_for(double seconds, const std::string& label, const Progress& progress,
                                const std::atomic<bool>* cancel) {
  if (!(seconds > 0)) throw CliError("run duration must be > 0");
  const uint64_t target = std::max<uint64_t>(1, uint64_t(std::llround(seconds * loop_rate_hz())));
  const int64_t id = begin(label, nullptr, "", target);
  return run_steps(target, id, label, progress, cancel);
}

RunSummary LiveRuns::run_ident(p::IdentStart start, const std::string& excitation_json, const std::string& label,
                                  const Progress& progress) {
  check_firmware_offers(start, p_.device.info(), p_.device.protocol_minor());
  if (start.duration == 0) throw CliError("an identification run must last at least one control step");
  const int64_t id = begin(label, &start, excitation_json, start.duration);
  return run_steps(start.duration, id, label, progress, nullptr);
}

// Polls the active run every 10 ms until it has made `target` steps or
// something ends it first.
LiveRuns::TimedEnd LiveRuns::wait_for_steps(uint64_t target, int64_t id, const Progress& progress,
                                            const std::atomic<bool>* cancel, std::chrono::steady_clock::time_point started) {
  using clock = std::chrono::steady_clock;
  ActiveRun& run = p_.run;
  const double rate = loop_rate_hz();
  const double seconds = double(target) / rate;
  // Telemetry may pause for a link outage the session rides out, or for a
  // slow line's decimation; longer than that, the firmware is not running
  // our run any more.
  const double period_s = double(std::max<uint16_t>(run.decimation.load(), 1)) / rate;
  const auto silence = std::max<clock::duration>(
      p_.options.session.silence_limit, std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(10 * period_s)));
  // A backstop for a step counter that never advances: twice the run, plus
  // the time to start.
  auto deadline = started + std::chrono::milliseconds(int64_t(seconds * 2000.0) + 5000);
  bool said_locked_out = false;
  while (true) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (cancel && cancel->load()) return {TimedEnd::Cancelled, ""};
    if (stop_timed_.exchange(false)) return {TimedEnd::Stopped, ""};
    if (interrupted()) return {TimedEnd::Interrupted, ""};
    // No more telemetry will come for a run someone else stopped; polling
    // on would only keep the caller (and a quitting TUI joining its worker)
    // waiting.
    if (run.id.load() != id) return {TimedEnd::StoppedElsewhere, ""};
    if (const std::string err = run.recorder.error(); !err.empty()) return {TimedEnd::RecordFailed, err};
    if (const std::string gone = p_.simulator.exit_words(); !gone.empty()) return {TimedEnd::Early, gone};
    if (run.recorder.locked_out() && !said_locked_out) {
      said_locked_out = true;
      p_.notices.say(fmt::format("database {} has been locked by another process for over {:g} s (--db-busy): run {}'s samples "
                      "are counted lost until it is released; the run goes on",
                      p_.db_path, std::chrono::duration<double>(p_.options.db_busy).count(), id));
    }
    if (run.step_went_back.load())
      return {TimedEnd::Early, fmt::format("the firmware's step count went back from {} to {} (a reset, or not this run's steps)",
                                           run.step_back_from.load(), run.step_back_to.load())};
    if (const uint8_t st = run.left_state.load(); st != 0 || run.left_watchdog.load() != 0)
      return {TimedEnd::Early, left_run_reason(st, run.left_watchdog.load(), p_.session.take_longest_write_gap())};
    const auto now = clock::now();
    if (run.have_last_step) {
      const uint64_t done = uint64_t(run.last_step.load() - run.first_step.load()) + run.decimation;
      if (progress) progress(std::min(done, target), target);
      if (done >= target) return {TimedEnd::Reached, ""};
    }
    if (run.user_hold.load()) {  // held on purpose: telemetry pauses, and so does the clock
      deadline += std::chrono::milliseconds(10);
      continue;
    }
    if (now > deadline)
      return {TimedEnd::Early, fmt::format("the firmware's step count did not reach {} steps in {:.0f} s", target,
                                           std::chrono::duration<double>(now - started).count())};
    const auto last = run.have_last_step ? clock::time_point(clock::duration(run.last_sample_ns.load())) : started;
    if (now - last > silence)
      return {TimedEnd::Early,
              run.have_last_step ? fmt::format("telemetry stopped arriving (none for {:.1f} s: firmware stopped or link lost)",
                                               std::chrono::duration<double>(now - last).count())
                                 : "no telemetry arrived after RUN_START"};
  }
}

// The silence a run ended early in, as a gap: the frames that fell due in
// it at the run's rate, at most the steps it still had to go. The steps it
// never reached after that are no gap (the run ended, as its end says), or
// a gap would outlast the run itself.
void LiveRuns::record_early_end_gap(int64_t id, uint64_t target, std::chrono::steady_clock::time_point started,
                                    const std::string& early) {
  using clock = std::chrono::steady_clock;
  ActiveRun& run = p_.run;
  const double rate = loop_rate_hz();
  const uint16_t d = std::max<uint16_t>(run.decimation.load(), 1);
  const uint64_t done = run.have_last_step ? uint64_t(run.last_step.load() - run.first_step.load()) + d : 0;
  const uint64_t missing = done >= target ? 0 : (target - done + d - 1) / d;
  const auto last = run.have_last_step ? clock::time_point(clock::duration(run.last_sample_ns.load())) : started;
  const double silent_s = std::chrono::duration<double>(clock::now() - last).count();
  const uint64_t lost = std::min(missing, uint64_t(silent_s * rate / d));
  const uint64_t k = run.k.load();
  if (missing > 0) {
    run.lost += lost;
    run.recorder.add_gap(id, k == 0 ? 0 : k - 1, lost, "run ended early: " + early, silent_s);
  }
}

// The run is stopped on the firmware whatever the database says; closing
// its row may fail like the rest of the writes did.
void LiveRuns::fail_recording(int64_t id, const std::string& label, const std::string& error) {
  std::string saved;
  try {
    const uint64_t kept = finish(id, label, "recording failed: " + error).metrics.samples;
    // Counted once the run is stopped: what came until RUN_STOP's ACK too.
    saved = fmt::format("{} of {} samples saved", kept, p_.run.k.load());
  } catch (const std::exception&) {
    // The same failure again, most likely: not worth repeating.
    saved = fmt::format("{} samples received; the run's row could not be closed either", p_.run.k.load());
  }
  throw CliError(fmt::format("run {} stopped at once: recording failed ({}); {}", id, error, saved));
}

RunSummary LiveRuns::run_steps(uint64_t target, int64_t id, const std::string& label, const Progress& progress,
                                  const std::atomic<bool>* cancel) {
  const auto started = std::chrono::steady_clock::now();
  stop_timed_ = false;
  timed_run_ = true;
  const TimedEnd end = wait_for_steps(target, id, progress, cancel, started);
  timed_run_ = false;
  const std::string early = end.kind == TimedEnd::Early ? end.words : "";
  if (!early.empty() && p_.run.id.load() == id) record_early_end_gap(id, target, started, early);
  if (end.kind == TimedEnd::RecordFailed) fail_recording(id, label, end.words);
  RunSummary s = finish(id, label,
                        end.kind == TimedEnd::Reached       ? "completed"
                        : end.kind == TimedEnd::Stopped     ? "stopped by the user"
                        : end.kind == TimedEnd::Cancelled   ? "cancelled"
                        : end.kind == TimedEnd::Interrupted ? interrupt_reason()
                                                            : "ended early: " + early);
  if (end.kind == TimedEnd::StoppedElsewhere || end.kind == TimedEnd::Stopped || end.kind == TimedEnd::Cancelled)
    return s;
  if (end.kind == TimedEnd::Interrupted)
    throw CliError(fmt::format("{}: run {} stopped and kept ({} samples)", interrupt_reason(), s.run_id,
                               s.metrics.samples));
  if (!early.empty()) {
    s.ended_early = true;
    p_.notices.say(fmt::format("run {} ended early: {}", s.run_id, early));
  }
  return s;
}

std::optional<RunSummary> LiveRuns::end_simulator_gone() {
  const std::string words = p_.simulator.exit_words();
  if (words.empty()) return std::nullopt;
  // A timed run (run_for) sees the same and ends itself, with its missing
  // steps as the gap.
  if (timed_run_.load()) return std::nullopt;
  std::lock_guard<std::mutex> stopping(stop_mu_);
  ActiveRun& run = p_.run;
  const int64_t id = run.id.load();
  if (id == 0) return std::nullopt;
  using clock = std::chrono::steady_clock;
  const auto last = run.have_last_step ? clock::time_point(clock::duration(run.last_sample_ns.load())) : run.started();
  const double silent_s = std::chrono::duration<double>(clock::now() - last).count();
  // The frames the run would have had from its last sample to now.
  const uint64_t missed =
      uint64_t(std::llround(silent_s * loop_rate_hz() / std::max<uint16_t>(run.decimation.load(), 1)));
  const uint64_t k = run.k.load();
  run.lost += missed;
  run.recorder.add_gap(id, k == 0 ? 0 : k - 1, missed, words, silent_s);
  return stop_locked(id, words);
}

double LiveRuns::loop_rate_hz() const {
  const double rate = double(p_.device.info().loop_rate_hz);
  return rate > 0 ? rate : 100.0;
}

std::optional<RunSummary> LiveRuns::last() const {
  std::lock_guard<std::mutex> lock(mu_);
  return last_run_;
}

std::vector<int64_t> LiveRuns::session_runs() const {
  std::lock_guard<std::mutex> lock(mu_);
  return session_runs_;
}

RunMetrics LiveRuns::metrics(int64_t run_id, double skip_s, double window_s) {
  RunStore store(p_.db_path);
  return run_metrics(store, run_id, skip_s, window_s);
}

}  // namespace nlsoft::console
