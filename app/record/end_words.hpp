#pragma once
// Why a run ended, in a word or two, for a column (`runs list`): the
// recording keeps the whole sentence ("ended early: the firmware's link
// watchdog tripped (nothing from the console for watchdog_ms); it is
// holding"), which `runs show` prints.
#include <string>

namespace nlsoft::console {

// "finished", "stopped", "early: watchdog", "unfinished", ... from a run's
// ended_at (empty: never closed) and end_reason.
std::string end_words(const std::string& ended_at, const std::string& end_reason);

// "refused", "lost frames", "saturated", "early: silent", ... from why a
// tuning evaluation failed (its sentence is in the run's notes).
std::string failure_words(const std::string& failed);

}  // namespace nlsoft::console
