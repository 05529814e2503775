// Sample intake, on the link's reader thread: every TELEMETRY and
// IDENT_SAMPLE numbered into the run in progress (SENSOR_HEALTH recorded
// beside them), its gaps recorded, kept for the live plots and the UDP
// stream; STATUS watched for the firmware leaving the run.
#include "app/live/live_console.hpp"

#include <algorithm>
#include <chrono>

namespace nlsoft::console {

namespace p = nlsoft::protocol;
namespace tf = protocol::telemetry_field;

void LiveConsole::on_telemetry(const p::Telemetry& t, uint32_t lost_before) {
  on_sample(sample_from(t, 0, tick_rate_hz_.load()), (t.mask & tf::kStep) != 0, lost_before);
}

void LiveConsole::on_ident_sample(const p::IdentSample& t, uint32_t lost_before) {
  on_sample(sample_from(t, 0), true, lost_before);
}

void LiveConsole::on_sensor_health(const p::SensorHealth& h) {
  if (const int64_t run = run_id_.load(); run != 0) recorder_->add_sensor_health(run, h.step, h.invalid, h.age_ms);
}

void LiveConsole::on_sample(Sample s, bool has_step, uint32_t lost_before) {
  const int64_t run = run_id_.load();
  if (run == 0) {
    live_.push(s);
    if (udp_) udp_->push(s, 0);
    return;
  }
  const uint64_t k = run_k_.fetch_add(1);
  s.k = k;
  if (k == 0) first_step_ = s.step;
  if (lost_before > 0) {
    run_lost_ += lost_before;
    recorder_->add_gap(run, k == 0 ? 0 : k - 1, lost_before, "telemetry frames lost on the link");
  } else if (resync_after_gap_.exchange(false) && have_last_step_ && has_step) {
    const uint32_t d = std::max<uint16_t>(decimation_.load(), 1);
    const uint32_t missed = (s.step - last_step_.load()) / d;
    if (missed > 1) {
      run_lost_ += missed - 1;
      recorder_->add_gap(run, k == 0 ? 0 : k - 1, missed - 1, "link down");
    }
  }
  recorder_->add_sample(run, s);
  live_.push(s);
  if (udp_) udp_->push(s, run);
  last_step_ = s.step;
  have_last_step_ = true;
  last_sample_ns_ = std::chrono::steady_clock::now().time_since_epoch().count();
}

// The firmware ends a run on its own only through its link watchdog (or a
// fault): STATUS, sent every second, is where that shows, since telemetry
// just stops.
void LiveConsole::on_status(const p::Status& s) {
  tick_rate_hz_ = s.tick_rate_hz;
  note_uptime(s.uptime_ms);
  const int64_t run = run_id_.load();
  if (run != 0 && s.run_id == uint32_t(run) && s.run_state != uint8_t(p::RunState::Running) &&
      s.run_state != uint8_t(p::RunState::Ident) && !user_hold_.load()) {
    left_run_watchdog_ = s.watchdog;
    left_run_state_ = s.run_state;
  }
}

}  // namespace nlsoft::console
