#pragma once
// The reason a gap of samples lost to another process's database lock
// carries (Recorder), and how `runs show` knows such a gap: its duration is
// the time the lost samples span, not a silence of the telemetry.
#include <fmt/format.h>

#include <string>

namespace nlsoft::console {

inline constexpr const char* kLockGapPrefix = "database locked by another process for ";

inline std::string lock_gap_reason(double locked_s) { return fmt::format("{}{:.1f} s", kLockGapPrefix, locked_s); }

inline bool is_lock_gap(const std::string& reason) { return reason.rfind(kLockGapPrefix, 0) == 0; }

}  // namespace nlsoft::console
