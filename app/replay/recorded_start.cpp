#include "app/replay/recorded_start.hpp"

#include <fmt/format.h>

#include <map>

#include "app/live/reference_spec.hpp"
#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

// The simulator's INFO name (firmware/ports/posix/main.cpp): the firmware
// a replay can stand in for by running its code here.
constexpr const char* kSimulatorFirmware = "nlsoft-posix ";
// The database is outside input: a step count past this (23 days at 130 Hz)
// is no run a replay repeats step by step.
constexpr uint32_t kMaxReplaySteps = 1u << 28;

}  // namespace

RecordedStart recorded_start(RunStore& store, int64_t id, bool plant) {
  RecordedStart r;
  r.row = store.run(id);
  const RunRow& row = r.row;
  const std::string name = fmt::format("run {}", id);
  if (row.kind == "ident")
    throw CliError(fmt::format("{} is an identification run (open loop, the firmware's excitation on the inputs): "
                               "there is no controller to replay it through; replay a closed-loop run",
                               name));
  r.on_simulator = row.firmware.rfind(kSimulatorFirmware, 0) == 0;
  if (!r.on_simulator && !plant)
    throw CliError(fmt::format(
        "{} was recorded on {} ({}), not on the simulator: a board's run replays through a plant model trained "
        "from the rig's recorded runs: nlsoft-console train --rig {} --run ID... --plant --out {}.nlsp, then "
        "runs replay {} --plant {}.nlsp",
        name, row.firmware, row.platform, row.platform, row.platform, id, row.platform));
  if (row.samples == 0) throw CliError(fmt::format("{} has no samples: there is nothing to replay", name));

  bool first = true;
  store.for_each_sample(id, [&](const Sample& s) {
    if (!s.has(protocol::telemetry_field::kStep)) return;
    if (first) {
      r.first_step = s.step, first = false;
      if (s.has(protocol::telemetry_field::kYTrue)) {
        r.start_y.assign(s.y_true(), s.y_true() + s.n);
        r.start_l.assign(s.l, s.l + s.w);
        r.start_w = s.w;
      }
    }
    r.last_step = s.step;
  });
  if (first)
    throw CliError(fmt::format("{} recorded no step counts (telemetry without `step`): its length in control "
                               "steps is not known",
                               name));
  if (r.last_step >= kMaxReplaySteps)
    throw CliError(fmt::format("{} ends at step {}, past the {} steps a replay runs", name, r.last_step,
                               kMaxReplaySteps));
  r.reference = reference_from_json(row.reference, name);

  std::map<std::string, int> changed;
  for (const ParamRecord& p : store.params(id)) {
    if (p.at_start)
      r.params.emplace_back(p.name, p.value);
    else
      ++changed[p.name];
  }
  if (r.params.empty()) throw CliError(fmt::format("{} recorded no parameters at its start", name));
  for (const auto& [param, times] : changed)
    r.not_repeated.push_back(fmt::format("{} was changed {} time{} during {}; the replay keeps the value it started "
                                         "with",
                                         param, times, times == 1 ? "" : "s", name));
  return r;
}

}  // namespace nlsoft::console
