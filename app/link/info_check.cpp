#include "app/link/info_check.hpp"

#include <fmt/format.h>

namespace nlsoft::console {

namespace p = nlsoft::protocol;

std::string info_refusal(const p::Info& info) {
  if (info.n == 0 || info.n > p::kMaxTelemetryDim || info.m == 0 || info.m > p::kMaxTelemetryDim)
    return fmt::format("the firmware reports impossible dimensions n={} m={} (each 1..{})", info.n, info.m,
                       p::kMaxTelemetryDim);
  // An identification sample carries m + n + w floats in one frame.
  if (int(info.m) + info.n + info.w > p::kMaxIdentFloats)
    return fmt::format("the firmware reports impossible dimensions m={} n={} w={} (m + n + w at most {})", info.m,
                       info.n, info.w, p::kMaxIdentFloats);
  if (info.loop_rate_hz == 0 || info.loop_rate_hz > kMaxLoopRateHz)
    return fmt::format("the firmware reports a loop rate of {} Hz (a rig runs at 1..{} Hz)", info.loop_rate_hz,
                       kMaxLoopRateHz);
  return "";
}

}  // namespace nlsoft::console
