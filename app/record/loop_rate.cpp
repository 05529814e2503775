#include "app/record/loop_rate.hpp"

#include <fmt/format.h>

#include "app/record/run_metrics.hpp"

namespace nlsoft::console {

namespace {

std::string rate_text(double hz) {
  return hz >= 1000 ? fmt::format("{:.3g} kHz", hz / 1000) : fmt::format("{:.3g} Hz", hz);
}

bool measured(const RunMetrics& m) { return m.loop_rate_measured && m.loop_rate_set_hz > 0; }

}  // namespace

std::string loop_rate_text(const RunMetrics& m) {
  if (!measured(m))
    return fmt::format("loop {} set (not measured: fewer than 2 samples)", rate_text(m.loop_rate_set_hz));
  // No board's timer steps faster than it was set: a firmware that did
  // ran without one, as a --sim-fast simulator does, and its rate against
  // the set one says nothing.
  if (m.loop_rate_hz > kFasterThanRealTime * m.loop_rate_set_hz)
    return fmt::format("loop {} set, stepped as fast as the host ran it ({}: a simulator without its clock, --sim-fast)",
                       rate_text(m.loop_rate_set_hz), rate_text(m.loop_rate_hz));
  return fmt::format("loop {} of {} set ({:.0f} %)", rate_text(m.loop_rate_hz), rate_text(m.loop_rate_set_hz),
                     100 * m.loop_rate_hz / m.loop_rate_set_hz);
}

std::string loop_rate_warning(const RunMetrics& m) {
  if (!measured(m) || m.loop_rate_hz >= kLoopRateWarnShare * m.loop_rate_set_hz) return "";
  return fmt::format("warning: the control loop kept {:.0f} % of its set rate ({} of {}): the firmware's steps came "
                     "late (a loaded machine, or a step slower than its period), so its time axis is stretched and a "
                     "timed run takes longer than its duration",
                     100 * m.loop_rate_hz / m.loop_rate_set_hz, rate_text(m.loop_rate_hz), rate_text(m.loop_rate_set_hz));
}

}  // namespace nlsoft::console
