#pragma once
// The control loop's rate as a run achieved it (the firmware's step count
// over its own time stamps) against the rate it was set to (INFO's, stored
// with the run). A loaded machine or a step slower than its period makes a
// run slower than asked, and its N seconds of steps take longer: said at the
// run's end and by `runs show`, never silently.
#include <string>

namespace nlsoft::console {

struct RunMetrics;

// Below this share of the set rate the run's summary warns.
constexpr double kLoopRateWarnShare = 0.95;
// Above this multiple of the set rate the firmware kept no clock (a
// --sim-fast simulator): the rate is named as such, not as a share.
constexpr double kFasterThanRealTime = 1.5;

// "loop 6.6 kHz of 10 kHz set (66 %)"; "loop 1 kHz set (not measured: fewer
// than 2 samples)" when the samples cannot tell; "loop 80 Hz set, stepped as
// fast as the host ran it (180 kHz: ...)" for a --sim-fast simulator's.
std::string loop_rate_text(const RunMetrics& m);

// "warning: the control loop kept 66 % of its set rate (6.6 kHz of 10 kHz):
// ..." when below kLoopRateWarnShare, else "".
std::string loop_rate_warning(const RunMetrics& m);

}  // namespace nlsoft::console
