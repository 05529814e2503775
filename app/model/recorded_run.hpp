#pragma once
// A run the console recorded, as training data. The database (app/record/)
// and `runs export --csv` hold the same columns per telemetry sample: its
// index k, the firmware's step and time, the command u and the measured
// output y_true (and the sensor readings l where a run holds them). Both
// become a RecordedRun, and one function turns that into the Series train
// takes, so a run and its export give the same training set.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "app/model/csv.hpp"
#include "app/model/plant_target.hpp"
#include "app/model/series.hpp"

namespace nlsoft::model {

struct RecordedRun {
  std::string name;  // "run 12", or the exported file's path: every message names it
  std::string rig;   // the rig's name recorded with the run; empty: not known (an export)
  int m = 0, n = 0;
  int w = -1;                             // < 0: no sensor readings recorded
  double rate_hz = 0;                     // the loop rate recorded with the run (0: not known)
  int horizon = 0;                        // the controller's N as the run started (0: not known)
  std::vector<int64_t> k, step, time_us;  // per sample; -1 where the sample lacks it
  std::vector<double> u, y, l;            // rows x m, n, w; NaN where the sample lacks it
  long rows() const { return static_cast<long>(k.size()); }
};

// The run as a Series for `target`: u, y = y_true, l and the time base
// (the firmware's microseconds) from the run. A sample lacking u, y_true or
// l is left out; the Series breaks wherever two kept samples are not one
// control step apart (by the firmware's step count, else by k and time), so
// no history window spans a gap. Throws PipelineError, naming the run, for
// an empty run, one without a measured output or sensor readings the rig
// needs, a run of another rig or other dimensions.
Series recorded_series(const RecordedRun& run, const PlantTarget& target);

// `runs export --csv`'s columns: k,step,time_us,y_ref0..,y_hat0..,y_true0..,
// u0..,cost,iterations,compute_us, and l0.. when the run holds sensors.
bool is_run_export(const std::vector<std::string>& header);
RecordedRun run_from_export(const Table& t, const std::string& name);

// `train --data FILE`: a dataset (time,u0..,y0..,l0..) or a run export,
// told apart by the header; anything else is refused naming the file.
Series read_training_csv(const std::string& path, const PlantTarget& target);

// Reads run `id` from database `db` (empty: the console's default). The
// console supplies it (app/record/run_training.hpp); throws with the reason.
using RunLoader = std::function<RecordedRun(const std::string& db, int64_t id)>;

}  // namespace nlsoft::model
