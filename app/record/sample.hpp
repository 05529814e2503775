#pragma once
// One recorded control step: what a TELEMETRY frame carried, decoded, with
// compute time converted to microseconds; or what an IDENT_SAMPLE carried
// (u, the measured y in y_true, the sensors in l). Fixed size so the recorder queue
// never allocates per sample.
#include <cstdint>

#include "protocol/messages.hpp"

namespace nlsoft::console {

struct Sample {
  static constexpr int kMaxFloats = 4 * protocol::kMaxTelemetryDim;
  static constexpr int kMaxSensors = protocol::kMaxIdentFloats;
  uint64_t k = 0;  // index within the run, arrival order
  uint32_t step = 0, time_us = 0;
  uint8_t mask = 0, n = 0, m = 0, iterations = 0;
  uint8_t w = 0;  // sensors in l (identification runs; 0: none recorded)
  float cost = 0, compute_us = 0;
  float v[kMaxFloats] = {};  // y_ref[n] | y_hat[n] | y_true[n] | u[m]
  float l[kMaxSensors] = {};

  bool has(uint8_t field) const { return (mask & field) != 0; }
  const float* y_ref() const { return v; }
  const float* y_hat() const { return v + n; }
  const float* y_true() const { return v + 2 * n; }
  const float* u() const { return v + 3 * n; }
  float* y_ref() { return v; }
  float* y_hat() { return v + n; }
  float* y_true() { return v + 2 * n; }
  float* u() { return v + 3 * n; }
};

// The samples table's key: a run's samples form one contiguous rowid range.
inline int64_t sample_key(int64_t run_id, uint64_t k) { return (run_id << 32) | int64_t(k & 0xFFFFFFFFu); }

// tick_rate_hz from STATUS (0: unknown, compute_us stays 0).
Sample sample_from(const protocol::Telemetry& t, uint64_t k, uint32_t tick_rate_hz);
// An identification run's step: step, time, u, y (as y_true, when measured), l.
Sample sample_from(const protocol::IdentSample& t, uint64_t k);

}  // namespace nlsoft::console
