#pragma once
// A recorded run read back as training data for `train --run ID`
// (app/model/recorded_run.hpp): its rig name, dimensions and loop rate,
// and per sample k, step, time, u and y_true as the database holds them.
#include <cstdint>
#include <string>

#include "app/model/recorded_run.hpp"

namespace nlsoft::console {

// db empty: the console's default database. Throws CliError (no such run,
// an unreadable database) with the reason.
model::RecordedRun load_recorded_run(const std::string& db, int64_t id);

}  // namespace nlsoft::console
