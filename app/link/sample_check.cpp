#include "app/link/sample_check.hpp"

#include <fmt/format.h>

#include <cmath>

namespace nlsoft::console {

namespace p = nlsoft::protocol;
namespace tf = protocol::telemetry_field;

namespace {

bool finite(const float* v, int count) {
  for (int i = 0; i < count; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

// Before INFO: what a console sample holds (n and m share TELEMETRY's
// nibbles; an identification sample's sensors fill the rest).
bool ident_fits(const p::IdentSample& s) {
  return s.m <= p::kMaxTelemetryDim && s.n <= p::kMaxTelemetryDim && s.w <= p::kMaxIdentFloats;
}

}  // namespace

SampleFault telemetry_fault(const p::Telemetry& t, const p::Info* info) {
  const bool shape = info ? t.n == info->n && t.m == info->m : t.n <= p::kMaxTelemetryDim && t.m <= p::kMaxTelemetryDim;
  if (!shape) return SampleFault::Dimensions;
  const bool values = (!(t.mask & tf::kYRef) || finite(t.y_ref, t.n)) && (!(t.mask & tf::kYHat) || finite(t.y_hat, t.n)) &&
                      (!(t.mask & tf::kYTrue) || finite(t.y_true, t.n)) && (!(t.mask & tf::kU) || finite(t.u, t.m)) &&
                      (!(t.mask & tf::kCost) || std::isfinite(t.cost));
  return values ? SampleFault::None : SampleFault::NotFinite;
}

SampleFault ident_sample_fault(const p::IdentSample& s, const p::Info* info) {
  // n is 0 when the firmware measures no output (PROTOCOL.md 7), else INFO's.
  const bool shape = info ? s.m == info->m && (s.n == 0 || s.n == info->n) && s.w == info->w && ident_fits(s)
                          : ident_fits(s);
  if (!shape) return SampleFault::Dimensions;
  return finite(s.u, s.m) && finite(s.y, s.n) && finite(s.l, s.w) ? SampleFault::None : SampleFault::NotFinite;
}

SampleFault sensor_sample_fault(const p::SensorSample& s, const p::Info* info) {
  // Before INFO only the frame's own bound (unpack's) holds it.
  if (info && s.w != info->w) return SampleFault::Dimensions;
  return finite(s.l, s.w) ? SampleFault::None : SampleFault::NotFinite;
}

std::string telemetry_refusal(const p::Telemetry& t, const p::Info* info) {
  switch (telemetry_fault(t, info)) {
    case SampleFault::None: return "";
    case SampleFault::Dimensions:
      return info ? fmt::format("a TELEMETRY frame with n={} m={}, the firmware's INFO says n={} m={}", t.n, t.m,
                                info->n, info->m)
                  : fmt::format("a TELEMETRY frame with n={} m={}, more than a sample holds", t.n, t.m);
    case SampleFault::NotFinite: return fmt::format("a TELEMETRY frame (step {}) carrying NaN or infinity", t.step);
  }
  return "";
}

std::string ident_sample_refusal(const p::IdentSample& s, const p::Info* info) {
  switch (ident_sample_fault(s, info)) {
    case SampleFault::None: return "";
    case SampleFault::Dimensions:
      return info ? fmt::format("an IDENT_SAMPLE frame with m={} n={} w={}, the firmware's INFO says m={} n={} w={}",
                                s.m, s.n, s.w, info->m, info->n, info->w)
                  : fmt::format("an IDENT_SAMPLE frame with m={} n={} w={}, more than a sample holds", s.m, s.n, s.w);
    case SampleFault::NotFinite: return fmt::format("an IDENT_SAMPLE frame (step {}) carrying NaN or infinity", s.step);
  }
  return "";
}

std::string sensor_sample_refusal(const p::SensorSample& s, const p::Info* info) {
  switch (sensor_sample_fault(s, info)) {
    case SampleFault::None: return "";
    case SampleFault::Dimensions:
      return fmt::format("a SENSOR_SAMPLE frame with w={}, the firmware's INFO says w={}", s.w, info ? info->w : 0);
    case SampleFault::NotFinite: return fmt::format("a SENSOR_SAMPLE frame (step {}) carrying NaN or infinity", s.step);
  }
  return "";
}

}  // namespace nlsoft::console
