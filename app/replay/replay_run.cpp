#include "app/replay/replay_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "app/link/device.hpp"
#include "app/live/param_text.hpp"
#include "app/record/sample.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

namespace p = nlsoft::protocol;
namespace tf = protocol::telemetry_field;

std::vector<std::string> words_of(const std::string& text) {
  std::vector<std::string> w;
  std::string cur;
  for (char c : text) {
    if (c == ' ' || c == ',' || c == '\t') {
      if (!cur.empty()) w.push_back(cur), cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) w.push_back(cur);
  return w;
}

// The simulator's parameters, by PARAM_LIST, as a console learns them.
ParamCatalog catalog_of(SimulatorInProcess& sim, const p::InfoEx& info) {
  std::vector<ParamInfo> list;
  for (uint16_t i = 0;; ++i) {
    p::ParamList req;
    req.index = i;
    p::ParamDesc d;
    if (!sim.request(req).as(d)) break;
    list.push_back(param_info_from(d));
    if (i + 1u >= d.count) break;
  }
  apply_capacity(list, info.info.max_n, info.info.max_nc);
  return ParamCatalog(std::move(list));
}

template <class M>
void expect_ack(SimulatorInProcess& sim, const M& req, const std::string& what) {
  const SimFrame f = sim.request(req);
  p::Ack ack;
  if (!f.as(ack)) throw CliError(fmt::format("the simulator refused {}", what));
}

// The source's plant model, started where the run started; none: the
// simulator's plant.
PlantStandIn stand_in_of(const ReplaySource& src) {
  PlantStandIn p;
  if (!src.plant) return p;
  p.model = src.plant.get();
  p.start = src.start.start_channels();
  return p;
}

}  // namespace

ReplayRun::ReplayRun(const ReplaySource& src, uint32_t seed)
    : src_(src), sim_(src.rig, src.model->file, seed, stand_in_of(src)) {
  if (!sim_.request(p::InfoGet{}).as(info_)) throw CliError("the simulator in this process sent no INFO_EX");
  const RunRow& row = src.start.row;
  const bool same_model = info_.info.model_hash == row.model_hash;
  if (!src.model_given && !same_model)
    throw CliError(fmt::format("run {} ran model 0x{:08x}, not rig '{}''s shipped model {} (0x{:08x}): give --model "
                               "FILE, the model uploaded then (or another, to see what it would have done)",
                               src.id, row.model_hash, src.rig.name, src.model->path, info_.info.model_hash));
  if (!same_model) other_model_ = fmt::format("model {} (0x{:08x})", src.model->path, info_.info.model_hash);
  catalog_ = catalog_of(sim_, info_);
  for (const auto& [name, value] : src.start.params) {
    const ParamInfo* pi = catalog_.find(name);
    if (!pi) throw CliError(fmt::format("run {} recorded parameter '{}', which the simulator has not", src.id, name));
    set(*pi, value, fmt::format("run {}'s {} = {}", src.id, name, value));
  }
}

void ReplayRun::set(const ParamInfo& pi, const std::vector<double>& values, const std::string& what) {
  p::ParamSet req;
  req.id = pi.id;
  req.count = uint8_t(values.size());
  encode_param_values(pi, values, req.values);
  const SimFrame f = sim_.request(req);
  p::Nack nack;
  if (f.as(nack)) throw ParamRefused(nack, what.empty() ? describe_param_refusal(pi, nack, values)
                                         : fmt::format("{}: {}", what, describe_param_refusal(pi, nack, values)));
}

void ReplayRun::set(const ParamInfo& pi, const std::string& text, const std::string& what) {
  set(pi, parse_param_values(pi, expand_param_tokens(pi, words_of(text))), what);
}

std::vector<std::pair<ParamInfo, std::vector<double>>> ReplayRun::params() {
  std::vector<std::pair<ParamInfo, std::vector<double>>> all;
  for (const ParamInfo& pi : catalog_.all()) {
    p::ParamGet g;
    g.id = pi.id;
    p::ParamValue v;
    if (!sim_.request(g).as(v)) throw CliError(fmt::format("the simulator did not report {}", pi.name));
    all.emplace_back(pi, decode_param_values(pi, v.values, v.count));
  }
  return all;
}

void ReplayRun::prepare() {
  expect_ack(sim_, ref_select_of(src_.start.reference), "the run's reference");
  p::TelemetryConfig tc;
  tc.mask = tf::kAll;
  tc.decimation = uint16_t(std::max(src_.start.row.decimation, 1));
  decimation_ = tc.decimation;
  expect_ack(sim_, tc, "TELEMETRY_CONFIG");
  sensors_ = (info_.info.capabilities & p::capability::kSensorStream) != 0;
  if (sensors_) {
    p::SensorStream on;
    on.on = 1;
    expect_ack(sim_, on, "SENSOR_STREAM");
  }
  // At rest, as a simulator idles at neutral before a run.
  for (long k = 0; k < std::lround(2.0 * sim_.rate_hz()); ++k) sim_.step();
  sim_.take_frames();
}

RunInfo ReplayRun::run_info(const std::string& label, const std::string& notes) {
  const RunRow& row = src_.start.row;
  RunInfo ri;
  ri.label = label;
  ri.notes = notes;
  ri.platform = row.platform;
  ri.firmware = fmt::format("{} {}.{}.{} (in this process)", info_.info.firmware, info_.info.fw_major,
                            info_.info.fw_minor, info_.info.fw_patch);
  ri.model_hash = info_.info.model_hash;
  ri.loop_rate_hz = info_.info.loop_rate_hz;
  ri.n = info_.info.n;
  ri.m = info_.info.m;
  ri.decimation = decimation_;
  ri.reference = row.reference;
  ri.kind = "replay";
  ri.w = sensors_ ? info_.info.w : 0;
  for (const auto& [pi, values] : params()) ri.params.emplace_back(pi.name, format_param_values(pi, values));
  p::InfoEx now;
  if (const SimFrame f = sim_.request(p::InfoGet{}); f.as(now)) ri.param_hash = now.info.param_hash;
  return ri;
}

uint64_t ReplayRun::record(Recorder& recorder, int64_t id, const Progress& progress) {
  p::RunStart rs;
  rs.run_id = uint32_t(id);
  expect_ack(sim_, rs, "RUN_START");
  const uint32_t steps = src_.steps();
  const int w = sensors_ ? info_.info.w : 0;
  uint64_t k = 0;
  p::SensorSample pending;
  bool have_pending = false;
  for (uint32_t step = 0; step < steps; ++step) {
    if (progress && step % 4096 == 0) progress(step, steps);
    sim_.step();
    // The console's keep-alives, as a live session sends them: the link
    // watchdog of the run's parameters stays fed.
    if (step % 10 == 0) sim_.request(p::Ping{});
    for (const SimFrame& f : sim_.take_frames()) {
      if (f.as(pending)) {
        have_pending = true;
        continue;
      }
      p::Telemetry t;
      if (!f.as(t)) continue;
      Sample s = sample_from(t, k++, 1000000u);
      if (have_pending && pending.step == t.step && pending.w == w) {
        s.w = uint8_t(w);
        std::copy(pending.l, pending.l + w, s.l);
      }
      have_pending = false;
      recorder.add_sample(id, s);
    }
    if (k % 8192 == 0) recorder.flush();
  }
  sim_.request(p::RunStop{});
  recorder.end_run(id, "completed", k, 0);
  if (progress) progress(steps, steps);
  return k;
}

}  // namespace nlsoft::console
