#pragma once
// Sample intake, on the link's reader thread: every TELEMETRY and
// IDENT_SAMPLE numbered into the run in progress (SENSOR_HEALTH recorded
// beside them), its gaps recorded, kept
// for the live plots and the UDP stream. Separate because it is the one
// part that runs at the loop's rate, on a thread nothing else may block.
#include <atomic>
#include <cstdint>

#include "app/live/active_run.hpp"
#include "app/live/live_buffer.hpp"
#include "app/live/udp_stream.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::console {

class SampleIntake {
 public:
  // The newest samples for the live plots (what a paused plot can scroll
  // back through): 30 s at 500 Hz, ~4 MB.
  static constexpr size_t kLiveSamples = 16384;

  // udp: null without --udp; it outlives every call here (LiveConsole).
  SampleIntake(ActiveRun& run, UdpStream* udp) : run_(run), udp_(udp) {}

  // The link's reader thread, from the session's callbacks.
  void on_telemetry(const protocol::Telemetry& t, uint32_t lost_before);
  void on_ident_sample(const protocol::IdentSample& t, uint32_t lost_before);
  void on_sensor_health(const protocol::SensorHealth& h);  // protocol 1.4: recorded beside the samples
  // Protocol 1.6: a closed-loop step's sensors, kept for the TELEMETRY of
  // the same step that follows it (PROTOCOL.md 9.6), recorded in its l.
  void on_sensor_sample(const protocol::SensorSample& s);
  // Converts compute ticks to microseconds; watches for the firmware
  // leaving the run.
  void on_status(const protocol::Status& s);

  // Any thread (the UI's plots, LiveRuns clearing it as a run starts).
  LiveBuffer& live() { return live_; }

  // The firmware's latest SENSOR_HEALTH (a rig with sensor chips), run or
  // not: bit i of `invalid` is sensor channel i without a valid sample.
  struct Health {
    bool known = false;  // none has arrived (a rig without chips sends none)
    uint32_t invalid = 0;
    uint16_t age_ms = 0;
    double received_s_ago = 0;  // how long ago it arrived
  };
  Health health() const;

 private:
  // A run's sample from either message: numbered, gaps recorded, kept.
  void on_sample(Sample s, bool has_step, uint32_t lost_before);

  ActiveRun& run_;
  UdpStream* udp_;
  LiveBuffer live_{kLiveSamples};
  std::atomic<uint32_t> tick_rate_hz_{0};
  // Health packed in one word so a reader never sees half of it: bit 48
  // known, bits 32..47 age_ms, bits 0..31 invalid.
  std::atomic<uint64_t> health_{0};
  std::atomic<int64_t> health_at_ns_{0};  // steady clock
  // The latest SENSOR_SAMPLE, until a TELEMETRY takes it (the reader
  // thread's alone: both arrive there).
  protocol::SensorSample sensors_{};
  bool have_sensors_ = false;
};

}  // namespace nlsoft::console
