// The sensor stream (PROTOCOL.md 7 SENSOR_STREAM and SENSOR_SAMPLE, 9.6;
// protocol 1.6): with the SENSOR_STREAM capability, a value past 1 refused
// `out_of_range` on field 0; while on, every TELEMETRY of a closed-loop run
// preceded by a SENSOR_SAMPLE of its step and INFO's width, none stray;
// once off, none at all. Without the capability (a rig without sensors, or
// an older firmware) the request is refused `unsupported`. The stream is
// left off, as the firmware boots.
#include <fmt/format.h>

#include <thread>

#include "app/conformance/suite.hpp"

namespace nlsoft::console::conformance {

namespace {

using Clock = std::chrono::steady_clock;

Frame stream(Suite& s, uint8_t on) {
  p::SensorStream req;
  req.on = on;
  return s.pr.request(req);
}

// A short closed-loop run at every step, its TELEMETRY recorded with the
// width of the SENSOR_SAMPLE before each (-1: none came); empty when the
// run did not start (`why` says so).
std::vector<TelemetrySample> short_run(Suite& s, std::string& why) {
  p::TelemetryConfig tc;
  tc.mask = uint8_t(s.telemetry_mask | p::telemetry_field::kStep);
  tc.decimation = uint16_t(std::max<uint32_t>(1, s.info.info.loop_rate_hz / 200));
  const Frame c = s.pr.request(tc);
  if (!acked(c, p::MsgType::TelemetryConfig)) {
    why = "TELEMETRY_CONFIG: " + describe(c);
    return {};
  }
  p::RunStart start;
  start.run_id = 0x5E550000u | (s.random() & 0xFFFFu);
  s.pr.record_telemetry(true);
  const Frame f = s.pr.request(start);
  if (!acked(f, p::MsgType::RunStart)) {
    s.pr.record_telemetry(false);
    why = "RUN_START: " + describe(f);
    return {};
  }
  const auto until = Clock::now() + std::chrono::milliseconds(400);
  while (Clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    s.pr.request(p::Ping{});  // feeds the link watchdog
  }
  s.pr.request(p::RunStop{});
  s.pr.request(p::Ping{});  // behind every frame of the run
  s.pr.record_telemetry(false);
  return s.pr.telemetry();
}

}  // namespace

void check_sensor_stream(Suite& s) {
  s.group("sensor_stream");
  if (!(s.info.info.capabilities & p::capability::kSensorStream)) {
    // An older firmware may not answer a type it does not know: not asked.
    if (s.info.protocol_minor < 6) {
      s.check("sensor_stream", true,
              fmt::format("protocol 1.{}: no sensor stream (protocol 1.6), nothing to check", s.info.protocol_minor));
      return;
    }
    // Nothing to stream: the request is refused as the capability says.
    const Frame f = stream(s, 1);
    s.check("sensor_stream", nacked(f, p::StatusCode::Unsupported, p::kNoField, p::kNoField),
            fmt::format("without the SENSOR_STREAM capability (w {}): SENSOR_STREAM refused by {}", s.info.info.w,
                        describe(f)));
    return;
  }
  std::vector<std::string> faults;
  const Frame bad = stream(s, 2);
  if (!nacked(bad, p::StatusCode::OutOfRange, 0, p::kNoField))
    faults.push_back(fmt::format("on=2 answered by {} (out_of_range, field 0 expected)", describe(bad)));
  const Frame on = stream(s, 1);
  if (!acked(on, p::MsgType::SensorStream)) {
    s.check("sensor_stream", false, "on=1 answered by " + describe(on));
    return;
  }
  std::string why;
  const std::vector<TelemetrySample> with = short_run(s, why);
  const unsigned stray = s.pr.stray_sensor_samples();
  const Frame off = stream(s, 0);
  if (!acked(off, p::MsgType::SensorStream)) faults.push_back("on=0 answered by " + describe(off));
  const std::vector<TelemetrySample> without = why.empty() ? short_run(s, why) : std::vector<TelemetrySample>{};
  // Back to the mask in force before, every control step.
  p::TelemetryConfig back;
  back.mask = s.telemetry_mask;
  back.decimation = 1;
  s.pr.request(back);
  if (!why.empty()) {
    s.check("sensor_stream", false, why);
    return;
  }
  size_t paired = 0, wrong_width = 0;
  for (const TelemetrySample& t : with) {
    if (t.sensors_w == int(s.info.info.w)) ++paired;
    else if (t.sensors_w >= 0) ++wrong_width;
  }
  size_t unasked = 0;
  for (const TelemetrySample& t : without) unasked += t.sensors_w >= 0;
  if (with.size() < 3) faults.push_back(fmt::format("{} TELEMETRY frames while on", with.size()));
  if (paired != with.size())
    faults.push_back(fmt::format("{} of {} TELEMETRY frames preceded by a SENSOR_SAMPLE of their step and w {}{}",
                                 paired, with.size(), s.info.info.w,
                                 wrong_width ? fmt::format(" ({} of another width)", wrong_width) : std::string()));
  if (stray) faults.push_back(fmt::format("{} SENSOR_SAMPLE frames not followed by their step's TELEMETRY", stray));
  if (unasked || s.pr.stray_sensor_samples())
    faults.push_back(fmt::format("{} SENSOR_SAMPLE frames after SENSOR_STREAM off", unasked + s.pr.stray_sensor_samples()));
  s.check("sensor_stream", faults.empty(),
          faults.empty() ? fmt::format("on=2 refused out_of_range; on: {} TELEMETRY frames each preceded by its step's "
                                       "SENSOR_SAMPLE of w {}; off: {} frames, none",
                                       with.size(), s.info.info.w, without.size())
                         : join(faults, "; "));
}

}  // namespace nlsoft::console::conformance
