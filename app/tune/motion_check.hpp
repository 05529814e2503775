#pragma once
// Whether a tuning session scores anything: nrmse divides a run's error by
// the reference's range over the window measured, so a window in which the
// reference barely moves (the slow start of a Swirl at hold=10, a hold)
// scores noise, and the best set found is meaningless. The first
// evaluation is checked and the session says what to change.
#include <string>
#include <vector>

#include "app/record/run_metrics.hpp"

namespace nlsoft::console {

// A reference that moves less than this share of the rig's task space (on
// its best-moving tracked axis) over the window "barely moves".
inline constexpr double kStillReferenceShare = 0.05;

// The warning, or "" when the reference moves enough. task: the rig's task
// space per axis (task_space(); empty: unknown, then only a reference that
// does not move at all is flagged).
std::string still_reference_warning(const RunMetrics& m, const std::vector<double>& task, double settle_s,
                                    double window_s);

}  // namespace nlsoft::console
