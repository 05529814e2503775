// Every sample is numbered into the run in progress (or only shown, with
// none); a link down or frames lost on the way are recorded as the run's
// gaps.
#include "app/live/sample_intake.hpp"

#include <algorithm>
#include <chrono>

namespace nlsoft::console {

namespace p = nlsoft::protocol;
namespace tf = protocol::telemetry_field;

void SampleIntake::on_telemetry(const p::Telemetry& t, uint32_t lost_before) {
  Sample s = sample_from(t, 0, tick_rate_hz_.load());
  // Its step's sensors came right before it; a SENSOR_SAMPLE of another
  // step (its own TELEMETRY lost) is no sensor reading of this one.
  // Only while the console asked for them, and only as many as it asked
  // for: the run's record says how many sensors its samples hold, and a
  // device that sends them unasked, or of another width, adds none.
  const uint8_t w = run_.sensors_w.load();
  if (w > 0 && have_sensors_ && sensors_.w == w && (t.mask & tf::kStep) && sensors_.step == t.step) {
    s.w = std::min<uint8_t>(w, Sample::kMaxSensors);
    std::copy(sensors_.l, sensors_.l + s.w, s.l);
  }
  have_sensors_ = false;
  on_sample(s, (t.mask & tf::kStep) != 0, lost_before);
}

void SampleIntake::on_sensor_sample(const p::SensorSample& s) {
  sensors_ = s;
  have_sensors_ = true;
}

void SampleIntake::on_ident_sample(const p::IdentSample& t, uint32_t lost_before) {
  on_sample(sample_from(t, 0), true, lost_before);
}

void SampleIntake::on_sensor_health(const p::SensorHealth& h) {
  health_ = uint64_t(1) << 48 | uint64_t(h.age_ms) << 32 | h.invalid;
  health_at_ns_ = std::chrono::steady_clock::now().time_since_epoch().count();
  live_.mark_invalid(h.step, h.invalid);
  if (const int64_t run = run_.id.load(); run != 0) run_.recorder.add_sensor_health(run, h.step, h.invalid, h.age_ms);
}

SampleIntake::Health SampleIntake::health() const {
  const uint64_t v = health_.load();
  const auto at = std::chrono::steady_clock::time_point(std::chrono::steady_clock::duration(health_at_ns_.load()));
  return {(v >> 48 & 1u) != 0, uint32_t(v), uint16_t(v >> 32),
          std::chrono::duration<double>(std::chrono::steady_clock::now() - at).count()};
}

void SampleIntake::on_sample(Sample s, bool has_step, uint32_t lost_before) {
  const int64_t run = run_.id.load();
  if (run == 0) {
    live_.push(s);
    if (udp_) udp_->push(s, 0);
    return;
  }
  // A step before the last one is no step of this run's progress: counted
  // lost, not recorded, and the run told (it ends early).
  if (has_step && run_.have_last_step && s.step < run_.last_step.load()) {
    if (!run_.step_went_back.exchange(true)) {
      run_.step_back_from = run_.last_step.load();
      run_.step_back_to = s.step;
    }
    run_.lost += 1 + lost_before;
    return;
  }
  // A timed run is its planned steps (ActiveRun::planned_steps): what
  // the firmware sends after them, before RUN_STOP reaches it, is neither
  // recorded nor lost, so the same run gives the same samples every time.
  if (const uint64_t plan = run_.planned_steps.load();
      plan != 0 && has_step && run_.k.load() > 0 && uint64_t(s.step - run_.first_step.load()) >= plan)
    return;
  const uint64_t k = run_.k.fetch_add(1);
  s.k = k;
  if (k == 0) run_.first_step = s.step;
  if (lost_before > 0) {
    run_.lost += lost_before;
    run_.recorder.add_gap(run, k == 0 ? 0 : k - 1, lost_before, "telemetry frames lost on the link");
  } else if (run_.resync_after_gap.exchange(false) && run_.have_last_step && has_step) {
    const uint32_t d = std::max<uint16_t>(run_.decimation.load(), 1);
    const uint32_t missed = (s.step - run_.last_step.load()) / d;
    if (missed > 1) {
      run_.lost += missed - 1;
      run_.recorder.add_gap(run, k == 0 ? 0 : k - 1, missed - 1, "link down");
    }
  }
  run_.recorder.add_sample(run, s);
  live_.push(s);
  if (udp_) udp_->push(s, run);
  run_.last_step = s.step;
  run_.have_last_step = true;
  run_.last_sample_ns = std::chrono::steady_clock::now().time_since_epoch().count();
}

// The firmware ends a run on its own only through its link watchdog (or a
// fault): STATUS, sent every second, is where that shows, since telemetry
// just stops.
void SampleIntake::on_status(const p::Status& s) {
  tick_rate_hz_ = s.tick_rate_hz;
  const int64_t run = run_.id.load();
  if (run != 0 && s.run_id == uint32_t(run) && s.run_state != uint8_t(p::RunState::Running) &&
      s.run_state != uint8_t(p::RunState::Ident) && !run_.user_hold.load()) {
    run_.left_watchdog = s.watchdog;
    run_.left_state = s.run_state;
  }
}

}  // namespace nlsoft::console
