#include "app/replay/replay_source.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>

#include "app/model/error.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sqlite.hpp"
#include "host/files/cli_error.hpp"
#include "host/paths/install_paths.hpp"
#include "host/rig/rig_catalog.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Lookup;
using host::Rig;
using host::find_model_file;
using host::load_rig_arg;

namespace {

// The rig the run was recorded on: its name, or --rig FILE for a rig file
// (whose name must be the run's).
Rig replay_rig(int64_t id, const std::string& rig_arg, const RunRow& row) {
  if (!rig_arg.empty()) {
    Rig rig = load_rig_arg(rig_arg);
    if (rig.name != row.platform)
      throw CliError(fmt::format("run {} was recorded on rig '{}', not on rig '{}' ({})", id, row.platform, rig.name,
                                 rig_arg));
    return rig;
  }
  try {
    return load_rig_arg(row.platform);
  } catch (const CliError& e) {
    throw CliError(fmt::format("run {} was recorded on rig '{}', which is no shipped rig ({}): give --rig FILE, its "
                               "rig file",
                               id, row.platform, e.what()));
  }
}

// --model, else the rig's shipped model (its hash is checked against the
// run's once the simulator runs it).
void replay_model(int64_t id, const std::string& model_arg, const Rig& rig, LoadedModel& out) {
  if (!model_arg.empty()) return load_model(model_arg, out);
  if (rig.model.file.empty())
    throw CliError(fmt::format("rig '{}' names no [model] file: give --model FILE, the model run {} ran", rig.name, id));
  const Lookup found = find_model_file(rig.model.file);
  if (found.found.empty())
    throw CliError(fmt::format("no model file {} for rig '{}'; looked in:{}\ngive --model FILE, the model run {} ran",
                               rig.model.file, rig.name, found.tried_lines(), id));
  load_model(found.found, out);
}

RecordedStart read_start(const std::string& db, int64_t id, bool plant = false) {
  try {
    RunStore store(db);
    return recorded_start(store, id, plant);
  } catch (const DbError& e) {
    throw CliError(e.what());
  }
}

ReplaySource with_rig(const std::string& db, int64_t id, RecordedStart start, Rig rig, const std::string& model_arg,
                      bool with_model = true) {
  ReplaySource src;
  src.id = id;
  src.db = db;
  src.start = std::move(start);
  src.rig = std::move(rig);
  const RunRow& row = src.start.row;
  if (std::lround(src.rig.rate_hz) != std::lround(row.loop_rate_hz))
    throw CliError(fmt::format("run {} ran at {:g} Hz, rig '{}' at {:g} Hz (a simulator started with --sim-rate): "
                               "not replayable as it ran",
                               id, row.loop_rate_hz, src.rig.name, src.rig.rate_hz));
  if (!with_model) return src;
  auto model = std::make_shared<LoadedModel>();
  replay_model(id, model_arg, src.rig, *model);
  src.model = std::move(model);
  src.model_given = !model_arg.empty();
  return src;
}

// --plant FILE: read, and checked against the run and its rig.
void replay_plant(ReplaySource& src, const std::string& path) {
  std::shared_ptr<::nlsoft::model::PlantModel> pm;
  try {
    pm = std::make_shared<::nlsoft::model::PlantModel>(::nlsoft::model::load_plant_model(path));
  } catch (const ::nlsoft::model::PipelineError& e) {
    throw CliError(e.what());
  }
  const Rig& rig = src.rig;
  const RecordedStart& st = src.start;
  if (pm->rig != rig.name || pm->m != rig.m() || pm->n != rig.n() || pm->w != rig.w())
    throw CliError(fmt::format("{} is a plant model of rig '{}' (m = {}, n = {}, w = {}), not of run {}'s rig '{}' "
                               "(m = {}, n = {}, w = {})",
                               path, pm->rig, pm->m, pm->n, pm->w, src.id, rig.name, rig.m(), rig.n(), rig.w()));
  if (std::lround(pm->rate_hz) != std::lround(st.row.loop_rate_hz))
    throw CliError(fmt::format("{} steps at {:g} Hz, run {} ran at {:g} Hz", path, pm->rate_hz, src.id,
                               st.row.loop_rate_hz));
  if (st.start_w < 0)
    throw CliError(fmt::format("run {}'s first sample holds no measured output (y_true): a plant model has no state "
                               "to start it from",
                               src.id));
  if (st.start_w != pm->w)
    throw CliError(fmt::format("run {}'s first sample holds {} sensor readings, rig '{}' has {}: a plant model starts "
                               "from all of them (a firmware of protocol 1.6 or later streams them in a run)",
                               src.id, st.start_w, rig.name, pm->w));
  src.plant = std::move(pm);
  src.plant_path = path;
}

}  // namespace

ReplaySource open_replay_source(const std::string& db, int64_t id, const std::string& rig_arg,
                                const std::string& model_arg, bool with_model, const std::string& plant_arg) {
  RecordedStart start = read_start(db, id, !plant_arg.empty());
  Rig rig = replay_rig(id, rig_arg, start.row);
  ReplaySource src = with_rig(db, id, std::move(start), std::move(rig), model_arg, with_model);
  if (!plant_arg.empty()) replay_plant(src, plant_arg);
  return src;
}

ReplaySource open_replay_source(const std::string& db, int64_t id, const Rig& rig, const std::string& model_arg,
                                const std::string& plant_arg) {
  RecordedStart start = read_start(db, id, !plant_arg.empty());
  if (rig.name != start.row.platform)
    throw CliError(fmt::format("run {} was recorded on rig '{}', not on this session's rig '{}'", id,
                               start.row.platform, rig.name));
  ReplaySource src = with_rig(db, id, std::move(start), rig, model_arg);
  if (!plant_arg.empty()) replay_plant(src, plant_arg);
  return src;
}

}  // namespace nlsoft::console
