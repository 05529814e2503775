#pragma once
// A recorded run read and checked once for replaying it, as many times as
// asked (`runs replay` once, `tune --replay` once per candidate): its start,
// the rig it ran on and the model to run. Every refusal is here, before
// anything runs or is recorded.
#include <cstdint>
#include <memory>
#include <string>

#include "app/model/plant_model.hpp"
#include "app/replay/recorded_start.hpp"
#include "app/simulate/model_loader.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

struct ReplaySource {
  int64_t id = 0;
  std::string db;
  RecordedStart start;
  host::Rig rig;
  std::shared_ptr<const LoadedModel> model;  // null when opened without one
  bool model_given = false;  // --model: another model than the run's may run
  // --plant: the plant model that stands in for the rig (null: the
  // simulator's plant), and the file it came from.
  std::shared_ptr<const model::PlantModel> plant;
  std::string plant_path;
  uint32_t steps() const { return start.last_step + 1; }
  double duration_s() const { return double(steps()) / start.row.loop_rate_hz; }
};

// Reads run `id` from `db` and checks it can be replayed as it ran
// (recorded_start's refusals; the rig, `rig_arg` when given, which must be
// the run's; its rate; the model, `model_arg` or the rig's shipped one,
// unless `with_model` is false: a replay through a controller that runs
// none, the PID baseline; the plant model `plant_arg` when given, which must
// be the rig's, at its rate, and the run must hold its first sample's
// output and sensors to start it there). Throws CliError naming the run.
ReplaySource open_replay_source(const std::string& db, int64_t id, const std::string& rig_arg,
                                const std::string& model_arg, bool with_model = true,
                                const std::string& plant_arg = "");
// The same with the rig already loaded (a session's: `tune replay=N` in a
// script), which must be the run's.
ReplaySource open_replay_source(const std::string& db, int64_t id, const host::Rig& rig,
                                const std::string& model_arg, const std::string& plant_arg = "");

}  // namespace nlsoft::console
