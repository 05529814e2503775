#include "app/record/run_training.hpp"

#include <cmath>
#include <cstdlib>

#include "host/files/cli_error.hpp"
#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"

namespace nlsoft::console {

using host::CliError;

namespace tf = protocol::telemetry_field;

// Above any controller's horizon (shared/capacity.hpp's N is far below).
constexpr long kMaxRecordedHorizon = 1000;

model::RecordedRun load_recorded_run(const std::string& db, int64_t id) {
  try {
    RunStore store(db.empty() ? default_db_path() : db);
    const RunRow row = store.run(id);
    model::RecordedRun r;
    r.name = "run " + std::to_string(id);
    r.rig = row.platform;
    r.m = row.m;
    r.n = row.n;
    r.rate_hz = row.loop_rate_hz;
    // A database is outside input: a horizon past any controller's (or no
    // number) is not known, not a loop of that length.
    for (const ParamRecord& p : store.params(id)) {
      if (!p.at_start || p.name != "N") continue;
      char* end = nullptr;
      const long n = std::strtol(p.value.c_str(), &end, 10);
      if (end != p.value.c_str() && *end == '\0' && n >= 1 && n <= kMaxRecordedHorizon) r.horizon = int(n);
    }
    // Sensors are kept by identification runs (schema v6) and by closed-loop
    // runs recorded with the sensor stream (protocol 1.6); r.w stays < 0
    // for a closed-loop run without them.
    if (row.w > 0) r.w = row.w;
    const double nan = std::nan("");
    store.for_each_sample(id, [&](const Sample& s) {
      r.k.push_back(int64_t(s.k));
      r.step.push_back(s.has(tf::kStep) ? int64_t(s.step) : -1);
      r.time_us.push_back(s.has(tf::kTime) ? int64_t(s.time_us) : -1);
      for (int i = 0; i < r.m; ++i) r.u.push_back(s.has(tf::kU) ? double(s.u()[i]) : nan);
      for (int j = 0; j < r.n; ++j) r.y.push_back(s.has(tf::kYTrue) ? double(s.y_true()[j]) : nan);
      for (int i = 0; i < r.w; ++i) r.l.push_back(s.w > 0 ? double(s.l[i]) : nan);
    });
    return r;
  } catch (const DbError& e) {
    throw CliError(e.what());
  }
}

}  // namespace nlsoft::console
