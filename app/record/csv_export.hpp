#pragma once
// A run's samples as CSV: one header line, one row per sample, floats with
// 9 significant digits so a reader gets the recorded f32 back exactly. The
// last column, t, is the step time (app/record/step_time.hpp), written with
// the shortest digits that give its double back; time_us is the firmware's
// clock as sent. Column names stay y_true0..: a rig's names and units go to
// the HDF5 export, which has room for them.
#include <string>
#include <vector>

#include "app/record/run_store.hpp"

namespace nlsoft::console {

// Writes to a temporary file next to `path` and renames it into place, so a
// failed export never leaves a half file under the requested name. Returns
// the number of rows. Throws CliError on I/O failure.
size_t export_run_csv(RunStore& store, int64_t run_id, const std::string& path);

// Several runs in one file: a first column `run` holds each row's run id
// (one run's file has none, as before). The runs must have the same n and
// m (one header); every id is checked before anything is written.
size_t export_runs_csv(RunStore& store, const std::vector<int64_t>& run_ids, const std::string& path);

}  // namespace nlsoft::console
