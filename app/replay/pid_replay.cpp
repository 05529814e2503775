#include "app/replay/pid_replay.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "app/simulate/closed_loop.hpp"
#include "app/simulate/param_args.hpp"
#include "app/simulate/rig_loop.hpp"
#include "host/files/cli_error.hpp"
#include "host/rig/rig_params.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

// The limits run N clamped its inputs to, as it recorded them at its start.
std::vector<std::pair<std::string, std::string>> input_limits(const ReplaySource& src) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& p : src.start.params)
    if (p.first == "u_min" || p.first == "u_max") out.push_back(p);
  return out;
}

std::string gains_words(const host::RigPid& p) {
  std::string w = fmt::format("kp {:g}, ki {:g}, kd {:g}", p.kp, p.ki, p.kd);
  if (p.output_scale != 1) w += fmt::format(", output scale {:g}", p.output_scale);
  if (p.d_filter_tau != 0) w += fmt::format(", derivative filter {:g} s", p.d_filter_tau);
  return w;
}

}  // namespace

PidReplay record_pid_replay(const ReplaySource& src, uint32_t seed, const std::string& label,
                            const std::string& notes, Recorder& recorder,
                            const std::function<void(long, long)>& progress) {
  const host::Rig& rig = src.rig;
  const RunRow& row = src.start.row;
  LoopSetup setup;
  GenericPlantSpec generic{};
  // --plant: the plant model, held at the run's first sample with the
  // inputs at neutral until the loop's first step.
  StandInPlant stand_in;
  std::unique_ptr<model::PlantSimulator> plant_model;
  const std::vector<float> start = src.start.start_channels();
  if (src.plant) {
    plant_model = std::make_unique<model::PlantSimulator>(*src.plant);
    model::PlantSimulator* pm = plant_model.get();
    const int n = src.plant->n, w = src.plant->w;
    stand_in = {src.plant->m, n, w, float(1.0 / src.plant->rate_hz),
                [&rig, pm, &start](float* u) {
                  for (size_t i = 0; i < rig.inputs.size(); ++i) u[i] = float(rig.inputs[i].neutral);
                  pm->rest_at(start.data(), u);
                },
                [pm](const float* u) { pm->step(u); },
                [pm, n, w](float* y, float* l) {
                  std::copy(pm->channels(), pm->channels() + n, y);
                  std::copy(pm->channels() + n, pm->channels() + n + w, l);
                }};
    setup.stand_in = &stand_in;
  } else {
    use_rig_plant(rig, "runs replay --controller pid", generic, setup);
  }
  use_rig_pid(rig, setup);
  if (host::rig_params(rig, setup.params) != Status::Ok)
    throw CliError(fmt::format("rig '{}' ({}) exceeds the console's controller", rig.name, rig.file));
  const auto limits = input_limits(src);
  std::vector<ParamWrite> writes;
  for (const auto& [name, text] : limits) writes.push_back(parse_param_write(name + "=" + text, rig.m(), rig.n()));
  apply_param_writes(setup.params, writes, rig.m(), rig.n());
  setup.reference = src.start.reference;
  setup.steps = long(src.steps());
  setup.settle_steps = long(2.0 * rig.rate_hz);
  setup.seed = seed;
  const Trace t = run_closed_loop(setup, progress);

  PidReplay out;
  out.gains = gains_words(rig.pid);
  RunInfo ri;
  ri.label = label;
  ri.notes = fmt::format("{}; the rig file's PID baseline ({}), offline, as simulate --controller pid runs it", notes,
                         out.gains);
  ri.platform = row.platform;
  ri.firmware = "PID baseline (in this process)";
  ri.loop_rate_hz = row.loop_rate_hz;
  ri.n = t.n;
  ri.m = t.m;
  ri.reference = row.reference;
  ri.kind = "replay";
  ri.params = limits;
  out.id = recorder.begin_run(ri);

  // Row k of the trace is the instant after input u(k): the reference and
  // the plant's output there, paired as a recorded sample pairs them.
  namespace tf = protocol::telemetry_field;
  const size_t n = size_t(t.n), m = size_t(t.m);
  for (long k = 0; k < t.rows(); ++k) {
    Sample s;
    s.k = uint64_t(k);
    s.step = uint32_t(k + 1);
    s.time_us = uint32_t(std::llround(double(k + 1) * double(t.dt) * 1e6));
    s.mask = uint8_t(tf::kStep | tf::kTime | tf::kYRef | tf::kYTrue | tf::kU);
    s.n = uint8_t(n), s.m = uint8_t(m);
    std::copy_n(&t.y_ref[size_t(k) * n], n, s.y_ref());
    std::copy_n(&t.y_true[size_t(k) * n], n, s.y_true());
    std::copy_n(&t.u[size_t(k) * m], m, s.u());
    recorder.add_sample(out.id, s);
    if ((k + 1) % 8192 == 0) recorder.flush();
  }
  out.samples = uint64_t(t.rows());
  recorder.end_run(out.id, "completed", out.samples, 0);
  return out;
}

}  // namespace nlsoft::console
