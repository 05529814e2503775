#pragma once
// One replay of a recorded run (replay_source.hpp): the simulator's firmware
// in this process given the run's model and its parameters at its start,
// changes on top, then the run's reference for as many control steps as it
// lasted, each sample to a Recorder. Done in the steps below, in this order,
// so a replay with nothing changed gives the recording back bit for bit.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "app/link/device.hpp"
#include "app/link/param_catalog.hpp"
#include "app/record/recorder.hpp"
#include "app/replay/replay_source.hpp"
#include "app/replay/simulator_in_process.hpp"
#include "host/files/cli_error.hpp"

namespace nlsoft::console {

class ReplayRun {
 public:
  using Progress = std::function<void(size_t done, size_t total)>;

  // The simulator with noise seed `seed`, the source's model (refused
  // unless it is the run's or was given), the run's parameters at its start
  // in force. Throws CliError.
  ReplayRun(const ReplaySource& src, uint32_t seed);

  const ParamCatalog& catalog() const { return catalog_; }
  const protocol::InfoEx& info() const { return info_; }
  // The model runs is not the run's (a --model given): in words, else "".
  const std::string& other_model() const { return other_model_; }

  // A change: PARAM_SET of `values`. Throws ParamRefused (device.hpp, as a
  // board's refusal: for a tuner, a candidate outside the firmware's
  // feasible set) naming `what` (when not empty) and the NACK in the
  // parameter's words.
  void set(const ParamInfo& pi, const std::vector<double>& values, const std::string& what);
  // The same from text: numbers or a parameter's option names, separated
  // by spaces or commas ("1e6,2e6,1e6"), as --set and the recording write them.
  void set(const ParamInfo& pi, const std::string& text, const std::string& what);
  // Every parameter as in force now.
  std::vector<std::pair<ParamInfo, std::vector<double>>> params();

  // The run's reference and telemetry, the sensors streamed, then two
  // seconds at rest as a simulator idles before a run. Once, after the
  // changes, before run_info.
  void prepare();
  // The replay's row: the run's, with this firmware, model and every
  // parameter as in force, labelled and noted as given; kind "replay".
  RunInfo run_info(const std::string& label, const std::string& notes);
  // RUN_START as run `id`, the run's steps, each TELEMETRY recorded with the
  // SENSOR_SAMPLE sent right before it, RUN_STOP; the run closed. Returns
  // the samples recorded.
  uint64_t record(Recorder& recorder, int64_t id, const Progress& progress = {});

 private:
  const ReplaySource& src_;
  SimulatorInProcess sim_;
  protocol::InfoEx info_;
  ParamCatalog catalog_;
  std::string other_model_;
  uint16_t decimation_ = 1;
  bool sensors_ = false;
};

}  // namespace nlsoft::console
