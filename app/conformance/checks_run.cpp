// Run control, telemetry and the link watchdog (PROTOCOL.md 9.5-9.8).
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <thread>

#include "app/conformance/suite.hpp"
#include "app/conformance/watchdog_silence.hpp"

namespace nlsoft::console::conformance {

namespace {

using Clock = std::chrono::steady_clock;

Frame hold(Suite& s, uint8_t mode) {
  p::RunHold h;
  h.mode = mode;
  return s.pr.request(h);
}

bool configure_telemetry(Suite& s, uint8_t mask, uint16_t decimation, std::string& why) {
  p::TelemetryConfig tc;
  tc.mask = mask;
  tc.decimation = decimation;
  const Frame f = s.pr.request(tc);
  if (acked(f, p::MsgType::TelemetryConfig)) return true;
  why = fmt::format("TELEMETRY_CONFIG mask 0x{:02x}/{}: {}", mask, decimation, describe(f));
  return false;
}

}  // namespace

void check_run_control(Suite& s) {
  s.group("run");
  {
    const Frame f = hold(s, uint8_t(p::HoldMode::Hold));
    s.check("run_hold_idle", nacked(f, p::StatusCode::WrongState, 0, p::kNoField) ||
                                 nacked(f, p::StatusCode::WrongState, p::kNoField, p::kNoField),
            "RUN_HOLD with no run: " + describe(f));
  }
  // y_true needs its capability.
  {
    p::TelemetryConfig tc;
    tc.mask = p::telemetry_field::kYTrue;
    tc.decimation = 0;
    const Frame f = s.pr.request(tc);
    const bool has = s.info.info.capabilities & p::capability::kYTrue;
    s.check("telemetry_y_true", has ? acked(f, p::MsgType::TelemetryConfig)
                                    : nacked(f, p::StatusCode::Unsupported, 0, p::kNoField),
            fmt::format("mask y_true with{} the Y_TRUE capability: {}", has ? "" : "out", describe(f)));
  }
  std::string why;
  if (!configure_telemetry(s, p::telemetry_field::kStep, 0, why)) {
    s.check("run_start", false, why);
    return;
  }
  p::RunStart start;
  start.run_id = 0xC0F00000u | (s.random() & 0xFFFFu);
  const Frame sf = s.pr.request(start);
  const bool started = acked(sf, p::MsgType::RunStart);
  auto st = s.status();
  s.check("run_start", started && in_state(st, p::RunState::Running) && st->run_id == start.run_id,
          fmt::format("RUN_START run_id {}: {}; STATUS {} run_id {}", start.run_id, describe(sf), state_of(st),
                      st ? st->run_id : 0));
  if (started) {
    const Frame again = s.pr.request(start);
    p::RunStart other = start;
    other.run_id ^= 1;
    const Frame busy = s.pr.request(other);
    s.check("run_start_again", acked(again, p::MsgType::RunStart) &&
                                   (nacked(busy, p::StatusCode::WrongState, 0, p::kNoField) ||
                                    nacked(busy, p::StatusCode::WrongState, p::kNoField, p::kNoField)),
            fmt::format("the same run_id again: {}; another run_id: {}", describe(again), describe(busy)));
    const Frame bad = hold(s, 7);
    s.check("run_hold_bad_mode", nacked(bad, p::StatusCode::OutOfRange, 0, p::kNoField),
            "RUN_HOLD mode 7: " + describe(bad));
    std::vector<std::string> steps;
    bool ok = true;
    for (auto [mode, state] : {std::pair{p::HoldMode::Hold, p::RunState::Hold},
                               std::pair{p::HoldMode::Neutral, p::RunState::Neutral},
                               std::pair{p::HoldMode::Resume, p::RunState::Running}}) {
      const Frame f = hold(s, uint8_t(mode));
      st = s.status();
      ok = ok && acked(f, p::MsgType::RunHold) && in_state(st, state);
      steps.push_back(fmt::format("mode {}: {}, {}", int(mode), describe(f), state_of(st)));
    }
    s.check("run_hold", ok, join(steps, "; "));
  }
  const Frame stop = s.pr.request(p::RunStop{});
  const Frame stop2 = s.pr.request(p::RunStop{});
  st = s.status();
  s.check("run_stop", acked(stop, p::MsgType::RunStop) && acked(stop2, p::MsgType::RunStop) &&
                          in_state(st, p::RunState::Idle),
          fmt::format("RUN_STOP twice: {}, {}; STATUS {}", describe(stop), describe(stop2), state_of(st)));
}

// Every TELEMETRY frame generated is either received or counted in
// tx_dropped: frames generated = steps with step % decimation == 0.
void check_telemetry_rate(Suite& s) {
  s.group("telemetry");
  const uint16_t decimation = uint16_t(std::max<uint32_t>(1, s.info.info.loop_rate_hz / 200));
  std::string why;
  if (!configure_telemetry(s, p::telemetry_field::kAll & uint8_t(~(s.info.info.capabilities & p::capability::kYTrue
                                                                        ? 0
                                                                        : p::telemetry_field::kYTrue)),
                           decimation, why)) {
    s.check("telemetry", false, why);
    return;
  }
  const auto before = s.status();
  p::RunStart start;
  start.run_id = 0xC0F10000u | (s.random() & 0xFFFFu);
  s.pr.record_telemetry(true);
  const Frame sf = s.pr.request(start);
  if (!acked(sf, p::MsgType::RunStart)) {
    s.pr.record_telemetry(false);
    s.check("telemetry", false, "RUN_START: " + describe(sf));
    return;
  }
  // STATUS_GET meanwhile keeps the link watchdog fed.
  const auto until = Clock::now() + Ms(800);
  while (Clock::now() < until) {
    std::this_thread::sleep_for(Ms(150));
    s.pr.request(p::Ping{});
  }
  s.pr.request(p::RunStop{});
  const auto after = s.status();  // behind every TELEMETRY of the run
  s.pr.record_telemetry(false);
  const auto t = s.pr.telemetry();
  if (!before || !after || t.empty()) {
    s.check("telemetry", false, t.empty() ? "no TELEMETRY during the run" : "no STATUS");
    return;
  }
  uint32_t gaps = 0;
  bool steps_ok = t.front().step < decimation;
  for (size_t i = 1; i < t.size(); ++i) {
    gaps += uint16_t(t[i].tseq - t[i - 1].tseq - 1);
    const uint32_t dstep = t[i].step - t[i - 1].step;
    if (dstep % decimation != 0 || dstep / decimation != uint32_t(uint16_t(t[i].tseq - t[i - 1].tseq))) steps_ok = false;
  }
  const uint32_t generated = (after->step + decimation - 1) / decimation;
  const uint32_t lost = generated - uint32_t(t.size());
  const uint32_t dropped = after->tx_dropped - before->tx_dropped;
  s.check("telemetry", t.size() >= 3 && steps_ok,
          fmt::format("{} frames (decimation {}), tseq {}..{}, step {}..{}{}", t.size(), decimation, t.front().tseq,
                      t.back().tseq, t.front().step, t.back().step, steps_ok ? "" : ", tseq and step disagree"));
  s.check("telemetry_accounting", lost == dropped && gaps <= lost,
          fmt::format("{} steps: {} frames generated, {} received, {} missing ({} inside tseq gaps); tx_dropped +{}",
                      after->step, generated, t.size(), lost, gaps, dropped));
  // tseq runs on across runs (9.6): the next run's first frame carries the
  // tseq after the last one generated, whatever was dropped.
  {
    start.run_id ^= 1;
    s.pr.record_telemetry(true);
    const Frame again = s.pr.request(start);
    const auto until2 = Clock::now() + Ms(300);
    while (Clock::now() < until2 && s.pr.telemetry().empty()) std::this_thread::sleep_for(Ms(20));
    s.pr.request(p::RunStop{});
    s.pr.record_telemetry(false);
    const auto t2 = s.pr.telemetry();
    const uint16_t expected = uint16_t(t.front().tseq + generated);
    const bool ok = acked(again, p::MsgType::RunStart) && !t2.empty() && t2.front().step == 0 &&
                    t2.front().tseq == expected;
    s.check("tseq_across_runs", ok,
            t2.empty() ? "RUN_START again: " + describe(again) + ", no TELEMETRY"
                       : fmt::format("next run's first frame: step {} tseq {} (the previous run generated tseq {}..{})",
                                     t2.front().step, t2.front().tseq, t.front().tseq, uint16_t(expected - 1)));
  }
  // Back to the mask in force before, every control step.
  configure_telemetry(s, s.telemetry_mask, 1, why);
}

// The link watchdog: a run with a short watchdog_ms survives a console that
// keeps sending, goes to the safe state when it falls silent, says so, and
// resumes on RUN_HOLD resume.
void check_watchdog(Suite& s) {
  s.group("watchdog");
  const p::ParamDesc* wd = s.param("watchdog_ms");
  if (!wd) {
    s.check("watchdog", false, "no watchdog_ms parameter (PROTOCOL.md 9.8)");
    return;
  }
  std::string why;
  const uint32_t timeout_ms = kWatchdogCheckMs;
  if (!s.set(*wd, {timeout_ms}, why)) {
    s.check("watchdog", false, fmt::format("watchdog_ms = {}: {}", timeout_ms, why));
    return;
  }
  const uint8_t safe = watchdog_safe_state(s);
  configure_telemetry(s, s.telemetry_mask, 0, why);  // quiet, so heartbeats are what we hear
  // Traffic every fifth of the timeout keeps the run going, for two
  // timeouts of the firmware's clock (its uptime, not ours). A trip after
  // the firmware's clock stepped past the timeout between two replies that
  // we asked for a fifth of it apart says that the host did not run the
  // console or the target meanwhile (an emulator's clock follows the
  // host's), not that feeding fails: the run is started again, up to 3
  // times, and the detail says so.
  std::optional<p::Status> st;
  bool kept = false;
  uint32_t t0 = 0, step = 0, stepped = 0;  // stepped: the step that made the last run not count
  int attempt = 0;
  for (; attempt < 3; ++attempt) {
    if (attempt > 0) s.pr.request(p::RunStop{}), stepped = step;
    p::RunStart start;
    start.run_id = 0xC0F20000u | (s.random() & 0xFFFFu);
    const Frame sf = s.pr.request(start);
    if (!acked(sf, p::MsgType::RunStart)) {
      s.check("watchdog", false, "RUN_START: " + describe(sf));
      configure_telemetry(s, s.telemetry_mask, 1, why);
      return;
    }
    st = s.status();
    t0 = st ? st->uptime_ms : 0;
    step = 0;
    kept = in_state(st, p::RunState::Running) && (st->watchdog & p::watchdog_flags::kArmed);
    const auto give_up = Clock::now() + std::chrono::seconds(20);
    while (kept && st && st->uptime_ms - t0 < 2 * timeout_ms && Clock::now() < give_up) {
      std::this_thread::sleep_for(Ms(timeout_ms / 5));
      const uint32_t before = st->uptime_ms;
      st = s.status();
      if (st) step = std::max(step, st->uptime_ms - before);
      kept = in_state(st, p::RunState::Running) && !(st->watchdog & p::watchdog_flags::kTripped);
    }
    if (kept || step <= timeout_ms) break;
  }
  if (attempt == 3) --attempt;  // the third run is the verdict, whatever its clock did
  s.check("watchdog_fed", kept,
          fmt::format("STATUS_GET every {} ms for {} ms of firmware time: {}{}", timeout_ms / 5,
                      st ? st->uptime_ms - t0 : 0, state_of(st),
                      attempt == 0 ? ""
                                   : fmt::format(" (run {} of the check: in the one before, the firmware's clock "
                                                 "stepped {} ms between two replies asked {} ms apart: the host did "
                                                 "not run the console or the target meanwhile)",
                                                 attempt + 1, stepped, timeout_ms / 5)));
  // Silence from our last frame on; the LOGs before it are dropped, so a
  // LOG after it is the link coming back.
  s.pr.take_logs();
  const uint32_t quiet_from = st ? st->uptime_ms : 0;
  const std::optional<p::Status> beat = heartbeat_after_silence(s, quiet_from, timeout_ms);
  s.check("watchdog_trips", watchdog_tripped(beat, safe),
          fmt::format("silent for {} ms of firmware time: heartbeat {} (expected run_state {}, watchdog bits armed and "
                      "tripped)",
                      beat ? beat->uptime_ms - quiet_from : 0, state_of(beat), safe));
  // The next frame: the link is back, LOG says so; STATUS still tripped.
  st = s.status();
  std::this_thread::sleep_for(Ms(100));
  const auto logs = s.pr.take_logs();
  s.check("watchdog_link_back", in_state(st, p::RunState(safe)) && !logs.empty(),
          fmt::format("after the silence: {}, LOG {}", state_of(st), logs.empty() ? "none" : "\"" + logs.back() + "\""));
  const Frame r = hold(s, uint8_t(p::HoldMode::Resume));
  st = s.status();
  s.check("watchdog_resume", acked(r, p::MsgType::RunHold) && in_state(st, p::RunState::Running) &&
                                 !(st->watchdog & p::watchdog_flags::kTripped),
          fmt::format("RUN_HOLD resume: {}; {}", describe(r), state_of(st)));
  s.pr.request(p::RunStop{});
  configure_telemetry(s, s.telemetry_mask, 1, why);
}

}  // namespace nlsoft::console::conformance
