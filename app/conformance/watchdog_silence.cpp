#include "app/conformance/watchdog_silence.hpp"

#include <thread>

namespace nlsoft::console::conformance {

uint8_t watchdog_safe_state(const Suite& s) {
  const p::ParamDesc* ss = s.param("safe_state");
  if (ss && s.original.at(ss->id).values[0] == 0) return uint8_t(p::RunState::Hold);
  return uint8_t(p::RunState::Neutral);
}

std::optional<p::Status> heartbeat_after_silence(Suite& s, uint32_t quiet_from, uint32_t timeout_ms) {
  using Clock = std::chrono::steady_clock;
  s.pr.take_statuses();
  std::optional<p::Status> beat;
  const auto deadline = Clock::now() + std::chrono::seconds(20);
  while (Clock::now() < deadline) {
    std::this_thread::sleep_for(Ms(100));
    for (const p::Status& b : s.pr.take_statuses()) beat = b;
    if (!beat) continue;
    const uint32_t quiet = beat->uptime_ms - quiet_from;
    // A beat past the timeout that says tripped settles it; waiting on for
    // the second timeout cost each conformance run about 1 s twice.
    if ((quiet > timeout_ms && (beat->watchdog & p::watchdog_flags::kTripped)) || quiet >= 2 * timeout_ms) break;
  }
  return beat;
}

bool watchdog_tripped(const std::optional<p::Status>& beat, uint8_t safe) {
  return beat && beat->run_state == safe && (beat->watchdog & p::watchdog_flags::kTripped) &&
         (beat->watchdog & p::watchdog_flags::kArmed);
}

}  // namespace nlsoft::console::conformance
