#pragma once
// Falling silent on a run the link watchdog guards (PROTOCOL.md 9.8): the
// closed-loop and the identification checks both do it and must judge it
// alike, so what the firmware falls to, how long we listen and what counts
// as tripped are said once.
#include <cstdint>
#include <optional>

#include "app/conformance/suite.hpp"

namespace nlsoft::console::conformance {

// The watchdog_ms both checks set: short enough to keep the checks brief,
// long enough that a loaded host feeding it every fifth of it never misses.
constexpr uint32_t kWatchdogCheckMs = 500;

// The run state a tripped watchdog leaves: safe_state as the suite found it
// (0 holds, anything else goes neutral); neutral when there is no such
// parameter.
uint8_t watchdog_safe_state(const Suite& s);

// Sends nothing and keeps only the heartbeats from now on, until one shows
// the firmware's clock (its uptime, not ours: an emulator's may lag) past
// the timeout with the watchdog tripped, or two timeouts past `quiet_from`,
// or 20 s of ours pass. The last one heard.
std::optional<p::Status> heartbeat_after_silence(Suite& s, uint32_t quiet_from, uint32_t timeout_ms);

// The heartbeat says the watchdog was armed, tripped, and left the run in `safe`.
bool watchdog_tripped(const std::optional<p::Status>& beat, uint8_t safe);

}  // namespace nlsoft::console::conformance
