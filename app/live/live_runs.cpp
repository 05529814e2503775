// The run's lifecycle: started (closed loop or identification), held,
// waited out for a duration with every way it can end early, stopped once
// whoever stops it, and its summary.
#include "app/live/live_console.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "host/files/cli_error.hpp"
#include "app/live/ident_plan.hpp"
#include "app/live/param_text.hpp"
#include "app/live/reference_spec.hpp"
#include "app/record/loop_rate.hpp"
#include "app/record/run_edit.hpp"
#include "app/record/run_store.hpp"

namespace nlsoft::console {

namespace p = nlsoft::protocol;

int64_t LiveConsole::start_run(const std::string& label) { return begin_run(label, nullptr, ""); }

int64_t LiveConsole::begin_run(const std::string& label, p::IdentStart* ident, const std::string& excitation_json) {
  if (running()) throw CliError(fmt::format("run {} is already active; stop it first", run_id_.load()));
  if (const std::string err = recorder_->error(); !err.empty()) throw CliError("recording has stopped: " + err);
  check_label(label);
  const p::Info info = device_->info();
  RunInfo ri;
  ri.label = label;
  ri.platform = device_->rig_label();
  ri.firmware = fmt::format("{} {}.{}.{}", info.firmware, info.fw_major, info.fw_minor, info.fw_patch);
  ri.model_hash = info.model_hash;
  ri.param_hash = info.param_hash;
  ri.loop_rate_hz = info.loop_rate_hz;
  ri.n = info.n;
  ri.m = info.m;
  decimation_ = ident ? std::max<uint16_t>(ident->decimation, 1) : telemetry_decimation_.load();
  ri.decimation = decimation_.load();
  if (ident) {
    // Open loop: no reference is followed.
    ri.kind = "ident";
    ri.w = info.w;
    ri.excitation = excitation_json;
  } else {
    {
      std::lock_guard<std::mutex> lock(mu_);
      ri.reference = reference_ ? reference_json(*reference_, reference_table_file_) : "";
    }
    if (ri.reference.empty()) ri.reference = firmware_reference_json();
  }
  for (const auto& [pi, v] : device_->get_all()) ri.params.emplace_back(pi.name, format_param_values(pi, v));
  const int64_t id = recorder_->begin_run(ri);
  run_k_ = 0;
  run_lost_ = 0;
  have_last_step_ = false;
  user_hold_ = false;
  left_run_state_ = 0;
  left_run_watchdog_ = 0;
  resync_after_gap_ = false;
  run_label_ = label;
  run_started_ns_ = std::chrono::steady_clock::now().time_since_epoch().count();
  live_.clear();
  run_id_ = id;
  try {
    if (ident) {
      ident->run_id = uint32_t(id);
      device_->ident_start(*ident);
    } else {
      device_->run_start(uint32_t(id));
    }
  } catch (const std::exception& e) {
    run_id_ = 0;
    decimation_ = telemetry_decimation_.load();
    recorder_->end_run(id, std::string("not started: ") + e.what(), 0, 0);
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
  session_->take_longest_write_gap();  // the run's own silences from here
  {
    std::lock_guard<std::mutex> lock(mu_);
    session_runs_.push_back(id);
  }
  return id;
}

RunSummary LiveConsole::stop_run(const std::string& reason) {
  std::lock_guard<std::mutex> stopping(stop_mu_);
  const int64_t id = run_id_.load();
  if (id == 0) throw CliError("no run is active");
  return stop_run_locked(id, reason);
}

RunSummary LiveConsole::finish_run(int64_t id, const std::string& label, const std::string& reason) {
  std::lock_guard<std::mutex> stopping(stop_mu_);
  if (run_id_.load() == id) return stop_run_locked(id, reason);
  // Someone else stopped it; their stop_run finished under stop_mu_.
  std::lock_guard<std::mutex> lock(mu_);
  if (last_run_ && last_run_->run_id == id) return *last_run_;
  RunSummary s;
  s.run_id = id;
  s.label = label;
  s.end_reason = "stopped";
  return s;
}

RunSummary LiveConsole::stop_run_locked(int64_t id, const std::string& reason) {
  std::string why = reason;
  // A simulator that has ended has nothing to stop: asking it would only
  // time out and bury the reason under "link lost at stop".
  if (simulator_exit().empty()) {
    try {
      device_->run_stop();
    } catch (const std::exception& e) {
      // Keeps why the run ended (an early end's cause comes first).
      why = reason + "; link lost at stop: " + e.what();
    }
  }
  // Every frame of the run came before RUN_STOP's ACK on the one reader.
  run_id_ = 0;
  decimation_ = telemetry_decimation_.load();
  recorder_->end_run(id, why, run_k_.load(), run_lost_.load());
  RunSummary s;
  s.run_id = id;
  s.label = run_label_;
  s.end_reason = why;
  s.metrics = metrics_of(id);
  if (const std::string w = loop_rate_warning(s.metrics); !w.empty()) say(fmt::format("run {}: {}", id, w));
  // Samples that arrived and could not be saved (a database locked past
  // --db-busy, a full queue) are in the run's gaps; say so at its end.
  if (const Recorder::Loss loss = recorder_->loss(id); loss.samples > 0)
    say(fmt::format("run {}: {} of {} samples saved; {} lost: {}", id, s.metrics.samples, run_k_.load(), loss.samples,
                    loss.reason));
  std::lock_guard<std::mutex> lock(mu_);
  last_run_ = s;
  return s;
}

void LiveConsole::hold(p::HoldMode mode) {
  if (!running()) throw CliError("no run is active");
  // Set before a hold is sent and cleared only after a resume is
  // acknowledged, so no STATUS of a held run reads as the firmware leaving it.
  if (mode != p::HoldMode::Resume) user_hold_ = true;
  device_->run_hold(mode);
  if (mode == p::HoldMode::Resume) user_hold_ = false;
  recorder_->add_link_event(run_id_.load(), "hold",
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

RunSummary LiveConsole::run_for(double seconds, const std::string& label, const Progress& progress,
                                const std::atomic<bool>* cancel) {
  if (!(seconds > 0)) throw CliError("run duration must be > 0");
  const int64_t id = start_run(label);
  const double rate = loop_rate_hz() > 0 ? loop_rate_hz() : 100.0;
  const uint64_t target = std::max<uint64_t>(1, uint64_t(std::llround(seconds * rate)));
  return run_steps(target, id, label, progress, cancel);
}

RunSummary LiveConsole::run_ident(p::IdentStart start, const std::string& excitation_json, const std::string& label,
                                  const Progress& progress) {
  check_firmware_offers(start, device_->info(), device_->protocol_minor());
  if (start.duration == 0) throw CliError("an identification run must last at least one control step");
  const int64_t id = begin_run(label, &start, excitation_json);
  return run_steps(start.duration, id, label, progress, nullptr);
}

RunSummary LiveConsole::run_steps(uint64_t target, int64_t id, const std::string& label, const Progress& progress,
                                  const std::atomic<bool>* cancel) {
  using clock = std::chrono::steady_clock;
  const double rate = loop_rate_hz() > 0 ? loop_rate_hz() : 100.0;
  const double seconds = double(target) / rate;
  // Telemetry may pause for a link outage the session rides out, or for a
  // slow line's decimation; longer than that, the firmware is not running
  // our run any more.
  const double period_s = double(std::max<uint16_t>(decimation_.load(), 1)) / rate;
  const auto silence = std::max<clock::duration>(
      options_.session.silence_limit, std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(10 * period_s)));
  const auto started = clock::now();
  // A backstop for a step counter that never advances: twice the run, plus
  // the time to start.
  auto deadline = started + std::chrono::milliseconds(int64_t(seconds * 2000.0) + 5000);
  std::string early, record_error;
  bool reached = false;
  bool interrupted = false, stopped = false, cancelled = false, stopped_elsewhere = false;
  bool said_locked_out = false;
  stop_timed_ = false;
  timed_run_ = true;
  while (true) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (cancel && cancel->load()) {
      cancelled = true;
      break;
    }
    if (stop_timed_.exchange(false)) {
      stopped = true;
      break;
    }
    if (LiveConsole::interrupted()) {
      interrupted = true;
      break;
    }
    // No more telemetry will come for a run someone else stopped; polling
    // on would only keep the caller (and a quitting TUI joining its worker)
    // waiting.
    if (run_id_.load() != id) {
      stopped_elsewhere = true;
      break;
    }
    if (const std::string err = recorder_->error(); !err.empty()) {
      record_error = err;
      break;
    }
    if (const std::string gone = simulator_exit(); !gone.empty()) {
      early = gone;
      break;
    }
    if (recorder_->locked_out() && !said_locked_out) {
      said_locked_out = true;
      say(fmt::format("database {} has been locked by another process for over {:g} s (--db-busy): run {}'s samples "
                      "are counted lost until it is released; the run goes on",
                      db_path_, std::chrono::duration<double>(options_.db_busy).count(), id));
    }
    if (const uint8_t st = left_run_state_.load(); st != 0 || left_run_watchdog_.load() != 0) {
      early = left_run_reason(st, left_run_watchdog_.load(), session_->take_longest_write_gap());
      break;
    }
    const auto now = clock::now();
    if (have_last_step_) {
      const uint64_t done = uint64_t(last_step_.load() - first_step_.load()) + decimation_;
      if (progress) progress(std::min(done, target), target);
      if (done >= target) {
        reached = true;
        break;
      }
    }
    if (user_hold_.load()) {  // held on purpose: telemetry pauses, and so does the clock
      deadline += std::chrono::milliseconds(10);
      continue;
    }
    if (now > deadline) {
      early = fmt::format("the firmware's step count did not reach {} steps in {:.0f} s", target,
                          std::chrono::duration<double>(now - started).count());
      break;
    }
    const auto last = have_last_step_ ? clock::time_point(clock::duration(last_sample_ns_.load())) : started;
    if (now - last > silence) {
      early = have_last_step_ ? fmt::format("telemetry stopped arriving (none for {:.1f} s: firmware stopped or link lost)",
                                            std::chrono::duration<double>(now - last).count())
                              : "no telemetry arrived after RUN_START";
      break;
    }
  }
  timed_run_ = false;
  if (!early.empty() && run_id_.load() == id) {
    // The silence the run ended in, as a gap: the frames that fell due in
    // it at the run's rate, at most the steps it still had to go. The steps
    // it never reached after that are no gap (the run ended, as its end
    // says), or a gap would outlast the run itself.
    const uint16_t d = std::max<uint16_t>(decimation_.load(), 1);
    const uint64_t done = have_last_step_ ? uint64_t(last_step_.load() - first_step_.load()) + d : 0;
    const uint64_t missing = done >= target ? 0 : (target - done + d - 1) / d;
    const auto last = have_last_step_ ? clock::time_point(clock::duration(last_sample_ns_.load())) : started;
    const double silent_s = std::chrono::duration<double>(clock::now() - last).count();
    const uint64_t lost = std::min(missing, uint64_t(silent_s * rate / d));
    const uint64_t k = run_k_.load();
    if (missing > 0) {
      run_lost_ += lost;
      recorder_->add_gap(id, k == 0 ? 0 : k - 1, lost, "run ended early: " + early, silent_s);
    }
  }
  if (!record_error.empty()) {
    // The run is stopped on the firmware whatever the database says; closing
    // its row may fail like the rest of the writes did.
    std::string saved;
    try {
      const uint64_t kept = finish_run(id, label, "recording failed: " + record_error).metrics.samples;
      // Counted once the run is stopped: what came until RUN_STOP's ACK too.
      saved = fmt::format("{} of {} samples saved", kept, run_k_.load());
    } catch (const std::exception&) {
      // The same failure again, most likely: not worth repeating.
      saved = fmt::format("{} samples received; the run's row could not be closed either", run_k_.load());
    }
    throw CliError(fmt::format("run {} stopped at once: recording failed ({}); {}", id, record_error, saved));
  }
  RunSummary s = finish_run(id, label,
                            reached       ? "completed"
                            : stopped     ? "stopped by the user"
                            : cancelled   ? "cancelled"
                            : interrupted ? interrupt_reason()
                                          : "ended early: " + early);
  if (stopped_elsewhere || stopped || cancelled) return s;
  if (interrupted)
    throw CliError(fmt::format("{}: run {} stopped and kept ({} samples)", interrupt_reason(), s.run_id,
                               s.metrics.samples));
  if (!early.empty()) {
    s.ended_early = true;
    say(fmt::format("run {} ended early: {}", s.run_id, early));
  }
  return s;
}

std::string LiveConsole::interrupt_reason() {
  switch (interrupted_flag().load()) {
    case SIGINT: return "interrupted by SIGINT (Ctrl-C)";
    case SIGTERM: return "interrupted by SIGTERM";
    case SIGHUP: return "interrupted by SIGHUP (the terminal closed or the connection dropped)";
    case SIGPIPE: return "interrupted by SIGPIPE (standard output's reader is gone)";
    case 0: return "not interrupted";
    default: return fmt::format("interrupted by signal {}", interrupted_flag().load());
  }
}

std::optional<RunSummary> LiveConsole::last_run() const {
  std::lock_guard<std::mutex> lock(mu_);
  return last_run_;
}

std::vector<int64_t> LiveConsole::session_runs() const {
  std::lock_guard<std::mutex> lock(mu_);
  return session_runs_;
}

RunMetrics LiveConsole::metrics_of(int64_t run_id, double skip_s, double window_s) {
  RunStore store(db_path_);
  return run_metrics(store, run_id, skip_s, window_s);
}

}  // namespace nlsoft::console
