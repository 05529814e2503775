#include "app/record/sample.hpp"

#include <algorithm>

namespace nlsoft::console {

Sample sample_from(const protocol::Telemetry& t, uint64_t k, uint32_t tick_rate_hz) {
  namespace tf = protocol::telemetry_field;
  Sample s;
  s.k = k;
  s.mask = t.mask;
  s.n = std::min<uint8_t>(t.n, protocol::kMaxTelemetryDim);  // the decoder's nibbles: at most 15 already
  s.m = std::min<uint8_t>(t.m, protocol::kMaxTelemetryDim);
  s.step = t.step;
  s.time_us = t.time_us;
  std::copy(t.y_ref, t.y_ref + s.n, s.y_ref());
  std::copy(t.y_hat, t.y_hat + s.n, s.y_hat());
  std::copy(t.y_true, t.y_true + s.n, s.y_true());
  std::copy(t.u, t.u + s.m, s.u());
  s.cost = t.cost;
  s.iterations = t.iterations;
  if ((t.mask & tf::kSolver) && tick_rate_hz > 0)
    s.compute_us = float(double(t.compute_ticks) * 1e6 / double(tick_rate_hz));
  return s;
}

Sample sample_from(const protocol::IdentSample& t, uint64_t k) {
  namespace tf = protocol::telemetry_field;
  Sample s;
  s.k = k;
  s.mask = uint8_t(tf::kStep | tf::kTime | tf::kU | (t.n ? tf::kYTrue : 0));
  // The session takes only frames of INFO's shape (app/link/sample_check);
  // the copies are bounded by what a Sample holds all the same, and n with
  // them: y_true() and u() are placed by n, so an n the copy was cut to
  // but the sample kept would put them past v.
  s.n = std::min<uint8_t>(t.n, protocol::kMaxTelemetryDim);
  s.m = std::min<uint8_t>(t.m, protocol::kMaxTelemetryDim);
  s.w = std::min<uint8_t>(t.w, Sample::kMaxSensors);
  s.step = t.step;
  s.time_us = t.time_us;
  std::copy(t.y, t.y + s.n, s.y_true());
  std::copy(t.u, t.u + s.m, s.u());
  std::copy(t.l, t.l + s.w, s.l);
  return s;
}

}  // namespace nlsoft::console
