// Identification runs (PROTOCOL.md 9.9, protocol 1.3): IDENT_START's
// refusals, the run's samples and inputs, hold/resume/stop, the end after
// its duration, and the link watchdog as in a closed-loop run.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "app/conformance/suite.hpp"
#include "app/conformance/watchdog_silence.hpp"

namespace nlsoft::console::conformance {

namespace {

using Clock = std::chrono::steady_clock;

// Waits until `n` samples came or `wait` passed; returns what came. Asks
// for STATUS every 100 ms meanwhile, as a console does (9.8): on a slow rig
// the samples take longer than the watchdog_ms the suite set.
std::vector<p::IdentSample> collect(Suite& s, size_t n, Ms wait) {
  std::vector<p::IdentSample> got;
  const auto until = Clock::now() + wait;
  auto fed = Clock::now();
  while (got.size() < n && Clock::now() < until) {
    std::this_thread::sleep_for(Ms(20));
    if (Clock::now() - fed >= Ms(100)) {
      s.status();
      fed = Clock::now();
    }
    for (p::IdentSample& x : s.pr.take_ident_samples()) got.push_back(x);
  }
  return got;
}

std::vector<float> limits(Suite& s, const char* name) {
  std::vector<float> v;
  if (const p::ParamDesc* d = s.param(name)) {
    const p::ParamValue& pv = s.original.at(d->id);
    for (uint8_t i = 0; i < pv.count; ++i) v.push_back(word_f32(pv.values[i]));
  }
  return v;
}

// A firmware without identification runs refuses IDENT_START as a left-out
// service (protocol 1.3 on); true when there are runs to check.
bool offers_ident(Suite& s, float rate) {
  if (!(s.info.info.capabilities & p::capability::kIdent) && s.info.protocol_minor >= 3) {
    p::IdentStart start;  // one the firmware would take, had it identification runs
    start.run_id = 0x1D000000u | (s.random() & 0xFFFFu);
    start.amplitude = 0.5f, start.band_lo = rate / 100.0f, start.band_hi = rate / 10.0f, start.duration = 10;
    s.left_out("ident_left_out", "identification runs", s.pr.request(start), p::kNoField);
    return false;
  }
  return s.offers(p::capability::kIdent, "IDENT", 3, "ident", "no identification runs to check");
}

// The run the checks start and vary: ten minutes of PRBS over the band a
// rig at `rate` can follow.
p::IdentStart base_run(Suite& s, float rate) {
  p::IdentStart base;
  base.run_id = 0x1D000000u | (s.random() & 0xFFFFu);
  base.signal = uint8_t(p::IdentSignal::Prbs);
  base.decimation = 1;
  base.seed = s.random();
  base.amplitude = 1.0f;
  base.band_lo = rate / 1000.0f;
  base.band_hi = rate / 10.0f;
  base.duration = uint32_t(rate * 600);
  return base;
}

// Refusals, each naming its field, and nothing started.
void check_refusals(Suite& s, const p::IdentStart& base, float rate) {
  struct Bad {
    const char* what;
    void (*edit)(p::IdentStart&, float);
    p::StatusCode status;
    uint8_t field;
  };
  const Bad bad[] = {
      {"signal 255", [](p::IdentStart& x, float) { x.signal = 255; }, p::StatusCode::OutOfRange, 1},
      {"decimation 0", [](p::IdentStart& x, float) { x.decimation = 0; }, p::StatusCode::OutOfRange, 3},
      {"amplitude NaN", [](p::IdentStart& x, float) { x.amplitude = std::nanf(""); }, p::StatusCode::NotFinite, 5},
      {"amplitude 2", [](p::IdentStart& x, float) { x.amplitude = 2.0f; }, p::StatusCode::OutOfRange, 5},
      {"band_lo 0", [](p::IdentStart& x, float) { x.band_lo = 0.0f; }, p::StatusCode::OutOfRange, 6},
      {"band_hi past rate/2", [](p::IdentStart& x, float r) { x.band_hi = r; }, p::StatusCode::OutOfRange, 7},
      {"band_lo > band_hi", [](p::IdentStart& x, float r) { x.band_lo = r / 4, x.band_hi = r / 8; },
       p::StatusCode::Inconsistent, 7},
      {"duration 0", [](p::IdentStart& x, float) { x.duration = 0; }, p::StatusCode::OutOfRange, 8},
  };
  std::vector<std::string> wrong;
  for (const Bad& b : bad) {
    p::IdentStart x = base;
    b.edit(x, rate);
    const Frame f = s.pr.request(x);
    if (!nacked(f, b.status, b.field, p::kNoField)) wrong.push_back(fmt::format("{}: {}", b.what, describe(f)));
  }
  const auto st = s.status();
  if (!in_state(st, p::RunState::Idle)) wrong.push_back("afterwards " + state_of(st));
  s.pr.take_ident_samples();
  s.check("ident_refusals", wrong.empty(),
          wrong.empty() ? fmt::format("{} bad IDENT_STARTs refused naming their field; still idle", std::size(bad))
                        : join(wrong, "; "));
}

// A run starts, samples arrive with the rig's dimensions, one a step.
// The samples, for the inputs' check.
std::vector<p::IdentSample> check_start(Suite& s, const p::IdentStart& base) {
  const p::Info& info = s.info.info;
  const Frame started = s.pr.request(base);
  const auto st = s.status();
  const bool ok_start = acked(started, p::MsgType::IdentStart) && in_state(st, p::RunState::Ident);
  std::vector<p::IdentSample> got = collect(s, 50, Ms(3000));
  bool dims = !got.empty(), steps = !got.empty();
  for (size_t k = 0; k < got.size(); ++k) {
    dims = dims && got[k].m == info.m && got[k].w == info.w && (got[k].n == info.n || got[k].n == 0);
    if (k > 0) steps = steps && got[k].step == got[k - 1].step + 1 && uint16_t(got[k].tseq - got[k - 1].tseq) == 1;
  }
  s.check("ident_starts", ok_start && dims && steps,
          fmt::format("IDENT_START: {}; {}; {} IDENT_SAMPLEs{}{}", describe(started), state_of(st), got.size(),
                      dims ? "" : ", m/n/w other than INFO's", steps ? " one a step" : ", steps or tseq skip"));
  return got;
}

// Every input of the run's samples inside u_min..u_max.
void check_inputs_in_limits(Suite& s, const std::vector<p::IdentSample>& got, const std::vector<float>& lo,
                            const std::vector<float>& hi) {
  std::string out;
  size_t moved = 0;
  for (size_t k = 0; k < got.size() && out.empty(); ++k)
    for (int i = 0; i < got[k].m && i < int(lo.size()) && i < int(hi.size()); ++i) {
      const float u = got[k].u[i];
      if (!(u >= lo[size_t(i)] && u <= hi[size_t(i)]))
        out = fmt::format("step {}: u[{}] = {:g} outside [{:g}, {:g}]", got[k].step, i, u, lo[size_t(i)], hi[size_t(i)]);
      if (k > 0 && u != got[k - 1].u[i]) ++moved;
    }
  s.check("ident_inputs_in_limits", !got.empty() && out.empty() && lo.size() == s.info.info.m,
          out.empty() ? fmt::format("{} samples, every input inside u_min..u_max; {} input changes", got.size(), moved)
                      : out);
}

// A retry is known by its run_id alone: taken whatever its other fields,
// and the run goes on (step not restarted); another run is refused.
void check_retry(Suite& s, const p::IdentStart& base) {
  const auto before = s.status();
  p::IdentStart retry = base;
  retry.signal = uint8_t(p::IdentSignal::Chirp);
  retry.seed = base.seed ^ 0x5A5A5A5Au;
  retry.duration = 1;
  const Frame again = s.pr.request(retry);
  const auto after = s.status();
  p::IdentStart other = base;
  other.run_id ^= 1;
  const Frame refused = s.pr.request(other);
  const bool went_on = in_state(after, p::RunState::Ident) && before && after->step >= before->step;
  s.check("ident_retry",
          acked(again, p::MsgType::IdentStart) && went_on && nacked(refused, p::StatusCode::WrongState, 0, p::kNoField),
          fmt::format("the same run_id with another signal, seed and duration: {}, step {} then {}; another "
                      "run_id: {}",
                      describe(again), before ? before->step : 0, state_of(after), describe(refused)));
}

// RUN_START with the identification run's own id is no retry of it.
void check_run_start_refused(Suite& s, const p::IdentStart& base) {
  p::RunStart r;
  r.run_id = base.run_id;
  const Frame f = s.pr.request(r);
  const auto st_after = s.status();
  s.check("ident_run_start_refused",
          nacked(f, p::StatusCode::WrongState, 0, p::kNoField) && in_state(st_after, p::RunState::Ident) &&
              st_after->run_id == base.run_id,
          fmt::format("RUN_START with the identification run's run_id: {}; then {}", describe(f), state_of(st_after)));
}

// The samples that come in 200 ms, after 100 ms for those already sent.
size_t samples_after_settling(Suite& s) {
  std::this_thread::sleep_for(Ms(100));
  s.pr.take_ident_samples();
  std::this_thread::sleep_for(Ms(200));
  return s.pr.take_ident_samples().size();
}

// Hold pauses the samples, resume brings them back, RUN_HOLD and RUN_STOP as in closed loop.
void check_hold_and_stop(Suite& s) {
  p::RunHold h;
  h.mode = uint8_t(p::HoldMode::Hold);
  const Frame held = s.pr.request(h);
  const auto st_held = s.status();
  const size_t while_held = samples_after_settling(s);
  const auto st_held_later = s.status();  // step stands still while held
  const bool frozen = st_held && st_held_later && st_held_later->step == st_held->step;
  h.mode = uint8_t(p::HoldMode::Resume);
  const Frame resumed = s.pr.request(h);
  const auto st_resumed = s.status();
  const size_t after = collect(s, 5, Ms(2000)).size();
  const Frame stop = s.pr.request(p::RunStop{});
  const auto st_stopped = s.status();
  const size_t after_stop = samples_after_settling(s);
  const bool ok = acked(held, p::MsgType::RunHold) && in_state(st_held, p::RunState::Hold) && while_held == 0 &&
                  frozen &&
                  acked(resumed, p::MsgType::RunHold) && in_state(st_resumed, p::RunState::Ident) && after >= 5 &&
                  acked(stop, p::MsgType::RunStop) && in_state(st_stopped, p::RunState::Idle) && after_stop == 0;
  s.check("ident_stops_on_hold_and_stop", ok,
          fmt::format("hold: {}, {} samples while held, 300 ms later step {}; resume: {}, {} samples; RUN_STOP: "
                      "{}, {} samples after",
                      state_of(st_held), while_held, st_held_later ? st_held_later->step : 0, state_of(st_resumed),
                      after, state_of(st_stopped), after_stop));
}

// A short run ends by itself after its duration: every step sent, idle, a
// LOG, and STATUS keeps its run_id with step = duration (the steps made).
void check_ends_after_duration(Suite& s, const p::IdentStart& base, float rate) {
  p::IdentStart shortrun = base;
  shortrun.run_id ^= 2;
  shortrun.signal = uint8_t(p::IdentSignal::Chirp);
  shortrun.duration = std::max<uint32_t>(10, uint32_t(rate / 5));
  s.pr.take_logs();
  const Frame f = s.pr.request(shortrun);
  const std::vector<p::IdentSample> all = collect(s, shortrun.duration, Ms(5000));
  std::this_thread::sleep_for(Ms(200));
  const auto after = s.status();
  const auto logs = s.pr.take_logs();
  const bool ok = acked(f, p::MsgType::IdentStart) && all.size() == shortrun.duration &&
                  all.back().step == shortrun.duration - 1 && in_state(after, p::RunState::Idle) && !logs.empty() &&
                  after->run_id == shortrun.run_id && after->step == shortrun.duration;
  s.check("ident_ends_after_duration", ok,
          fmt::format("{} steps asked: {} samples{}; then {}, {}", shortrun.duration, all.size(),
                      all.empty() ? "" : fmt::format(" (last step {})", all.back().step), state_of(after),
                      logs.empty() ? "no LOG" : "LOG \"" + logs.back() + "\""));
}

// The link watchdog: silence leads to the safe state, as in a closed-loop run.
void check_watchdog_trips(Suite& s, const p::IdentStart& base, float rate) {
  const p::ParamDesc* wd = s.param("watchdog_ms");
  std::string why;
  const uint32_t timeout_ms = kWatchdogCheckMs;
  if (!wd || !s.set(*wd, {timeout_ms}, why)) {
    s.check("ident_watchdog", false, wd ? fmt::format("watchdog_ms = {}: {}", timeout_ms, why) : "no watchdog_ms parameter");
    return;
  }
  const uint8_t safe = watchdog_safe_state(s);
  p::IdentStart watched = base;
  watched.run_id ^= 4;
  watched.decimation = uint16_t(std::max(1.0f, rate / 10));  // quiet: the heartbeat is what we listen to
  const Frame wf = s.pr.request(watched);
  const auto st0 = s.status();
  const uint32_t quiet_from = st0 ? st0->uptime_ms : 0;
  const std::optional<p::Status> beat = heartbeat_after_silence(s, quiet_from, timeout_ms);
  const bool tripped = acked(wf, p::MsgType::IdentStart) && watchdog_tripped(beat, safe);
  s.check("ident_watchdog", tripped,
          fmt::format("IDENT_START: {}; silent for {} ms of firmware time: heartbeat {} (expected run_state {}, "
                      "watchdog bits armed and tripped)",
                      describe(wf), beat ? beat->uptime_ms - quiet_from : 0, state_of(beat), safe));
  s.pr.request(p::RunStop{});
  s.pr.take_ident_samples();
  s.pr.take_logs();
}

}  // namespace

void check_ident(Suite& s) {
  s.group("ident");
  const p::Info& info = s.info.info;
  const float rate = float(info.loop_rate_hz ? info.loop_rate_hz : 100);
  if (!offers_ident(s, rate)) return;
  const p::IdentStart base = base_run(s, rate);
  check_refusals(s, base, rate);
  const std::vector<float> lo = limits(s, "u_min"), hi = limits(s, "u_max");
  check_inputs_in_limits(s, check_start(s, base), lo, hi);
  check_retry(s, base);
  check_run_start_refused(s, base);
  check_hold_and_stop(s);
  check_ends_after_duration(s, base, rate);
  check_watchdog_trips(s, base, rate);
}

}  // namespace nlsoft::console::conformance
