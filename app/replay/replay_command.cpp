#include "app/replay/replay_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "app/link/device.hpp"
#include "app/progress_bar.hpp"
#include "app/link/param_catalog.hpp"
#include "app/live/param_text.hpp"
#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"
#include "app/record/runs_command.hpp"
#include "app/record/sample.hpp"
#include "app/replay/recorded_start.hpp"
#include "app/replay/simulator_in_process.hpp"
#include "app/simulate/model_loader.hpp"
#include "host/files/cli_error.hpp"
#include "host/paths/install_paths.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_option.hpp"

namespace nlsoft::console {

namespace {

namespace p = nlsoft::protocol;
namespace tf = protocol::telemetry_field;

struct ReplayArgs {
  int64_t id = 0;
  std::string db, rig, model, label, svg, png;
  std::vector<std::string> sets;
  uint32_t seed = 1;
};

// The rig the run was recorded on: its name, or --rig FILE for a rig file
// (whose name must be the run's).
Rig replay_rig(const ReplayArgs& a, const RunRow& row) {
  if (!a.rig.empty()) {
    Rig rig = load_rig_arg(a.rig);
    if (rig.name != row.platform)
      throw CliError(fmt::format("run {} was recorded on rig '{}', not on rig '{}' ({})", a.id, row.platform, rig.name,
                                 a.rig));
    return rig;
  }
  try {
    return load_rig_arg(row.platform);
  } catch (const CliError& e) {
    throw CliError(fmt::format("run {} was recorded on rig '{}', which is no shipped rig ({}): give --rig FILE, its "
                               "rig file",
                               a.id, row.platform, e.what()));
  }
}

// --model, else the rig's shipped model (its hash is checked against the
// run's once the simulator runs it).
void replay_model(const ReplayArgs& a, const Rig& rig, LoadedModel& out) {
  if (!a.model.empty()) return load_model(a.model, out);
  if (rig.model.file.empty())
    throw CliError(fmt::format("rig '{}' names no [model] file: give --model FILE, the model run {} ran", rig.name, a.id));
  const Lookup found = find_model_file(rig.model.file);
  if (found.found.empty())
    throw CliError(fmt::format("no model file {} for rig '{}'; looked in:{}\ngive --model FILE, the model run {} ran",
                               rig.model.file, rig.name, found.tried_lines(), a.id));
  load_model(found.found, out);
}

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

// PARAM_SET of `words` (numbers, or a parameter's option names); throws
// CliError in the parameter's words, naming `what` (where the value came from).
void set_param(SimulatorInProcess& sim, const ParamInfo& pi, const std::vector<std::string>& words,
               const std::string& what) {
  const std::vector<double> values = parse_param_values(pi, expand_param_tokens(pi, words));
  p::ParamSet req;
  req.id = pi.id;
  req.count = uint8_t(values.size());
  encode_param_values(pi, values, req.values);
  const SimFrame f = sim.request(req);
  p::Nack nack;
  if (f.as(nack)) throw CliError(fmt::format("{}: {}", what, describe_param_refusal(pi, nack, values)));
}

template <class M>
void expect_ack(SimulatorInProcess& sim, const M& req, const std::string& what) {
  const SimFrame f = sim.request(req);
  p::Ack ack;
  if (!f.as(ack)) throw CliError(fmt::format("the simulator refused {}", what));
}

// Step for step against the recording: the steps both hold, and the
// largest differences of the plant's output and of the inputs.
struct Agreement {
  size_t steps = 0, identical = 0;
  double dy = 0, du = 0;
  uint32_t first_apart = 0;
  bool apart = false;
};

Agreement agreement(RunStore& store, int64_t recorded, int64_t replayed) {
  const RunSeries a = store.series(recorded), b = store.series(replayed);
  std::map<uint32_t, size_t> at;
  for (size_t i = 0; i < b.rows(); ++i) at[b.step[i]] = i;
  Agreement g;
  if (!a.has_y_true || !b.has_y_true || !a.has_u || !b.has_u || a.n != b.n || a.m != b.m) return g;
  for (size_t i = 0; i < a.rows(); ++i) {
    const auto it = at.find(a.step[i]);
    if (it == at.end()) continue;
    const size_t j = it->second;
    ++g.steps;
    double dy = 0, du = 0;
    for (int c = 0; c < a.n; ++c)
      dy = std::max(dy, double(std::fabs(a.y_true[i * size_t(a.n) + size_t(c)] - b.y_true[j * size_t(b.n) + size_t(c)])));
    for (int c = 0; c < a.m; ++c)
      du = std::max(du, double(std::fabs(a.u[i * size_t(a.m) + size_t(c)] - b.u[j * size_t(b.m) + size_t(c)])));
    if (dy == 0 && du == 0) {
      ++g.identical;
    } else if (!g.apart) {
      g.apart = true;
      g.first_apart = a.step[i];
    }
    g.dy = std::max(g.dy, dy), g.du = std::max(g.du, du);
  }
  return g;
}

// The run's parameters, then --set's, in force in the simulator; what
// differs from the run, in words (the model first when it is another).
std::vector<std::string> put_in_force(const ReplayArgs& a, SimulatorInProcess& sim, const ParamCatalog& catalog,
                                      const RecordedStart& start, const std::string& other_model) {
  for (const auto& [name, value] : start.params) {
    const ParamInfo* pi = catalog.find(name);
    if (!pi) throw CliError(fmt::format("run {} recorded parameter '{}', which the simulator has not", a.id, name));
    set_param(sim, *pi, words_of(value), fmt::format("run {}'s {} = {}", a.id, name, value));
  }
  std::vector<std::string> changes;
  if (!other_model.empty()) changes.push_back(other_model);
  for (const std::string& s : a.sets) {
    const size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size())
      throw CliError(fmt::format("--set {}: give NAME=VALUE (Q=1e6,2e6,1e6; Lambda=0.5)", s));
    const ParamInfo& pi = catalog.require(s.substr(0, eq));
    set_param(sim, pi, words_of(s.substr(eq + 1)), "--set " + s);
    changes.push_back(s);
  }
  return changes;
}

// The replay's row: the run's, changed as said, with the simulator's
// firmware, model and every parameter as they are now.
RunInfo replay_run_info(const ReplayArgs& a, const RunRow& row, p::InfoEx info, const ParamCatalog& catalog,
                        SimulatorInProcess& sim, const std::vector<std::string>& changes, uint16_t decimation,
                        bool sensors) {
  RunInfo ri;
  ri.label = !a.label.empty() ? a.label
                              : fmt::format("replay of run {}{}", a.id, changes.empty() ? "" : ": " + changes.front() +
                                                                           (changes.size() > 1 ? ", ..." : ""));
  ri.notes = fmt::format("runs replay {} (seed {}){}", a.id, a.seed,
                         changes.empty() ? std::string(", nothing changed") : ", changed: " + fmt::format("{}", fmt::join(changes, "; ")));
  ri.platform = row.platform;
  ri.firmware = fmt::format("{} {}.{}.{} (in this process)", info.info.firmware, info.info.fw_major,
                            info.info.fw_minor, info.info.fw_patch);
  ri.model_hash = info.info.model_hash;
  ri.loop_rate_hz = info.info.loop_rate_hz;
  ri.n = info.info.n;
  ri.m = info.info.m;
  ri.decimation = decimation;
  ri.reference = row.reference;
  ri.kind = "replay";
  ri.w = sensors ? info.info.w : 0;
  for (const ParamInfo& pi : catalog.all()) {
    p::ParamGet g;
    g.id = pi.id;
    p::ParamValue v;
    if (!sim.request(g).as(v)) throw CliError(fmt::format("the simulator did not report {}", pi.name));
    ri.params.emplace_back(pi.name, format_param_values(pi, decode_param_values(pi, v.values, v.count)));
  }
  if (const SimFrame f = sim.request(p::InfoGet{}); f.as(info)) ri.param_hash = info.info.param_hash;
  return ri;
}

// The run's steps again, each TELEMETRY recorded as run `id` with the
// SENSOR_SAMPLE sent right before it; the samples recorded.
uint64_t record_steps(SimulatorInProcess& sim, Recorder& recorder, int64_t id, uint32_t steps, int w,
                      ProgressBar& bar) {
  uint64_t k = 0;
  p::SensorSample pending;
  bool have_pending = false;
  for (uint32_t step = 0; step < steps; ++step) {
    if (step % 4096 == 0) bar.update(long(step), long(steps));
    sim.step();
    // The console's keep-alives, as a live session sends them: the link
    // watchdog of the run's parameters stays fed.
    if (step % 10 == 0) sim.request(p::Ping{});
    for (const SimFrame& f : sim.take_frames()) {
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
  return k;
}

// How the replay `id` agrees with the recording of run `of`, step for step.
void say_agreement(const std::string& db, int64_t of, int64_t id) {
  try {
    RunStore store(db);
    const Agreement g = agreement(store, of, id);
    if (g.steps == 0)
      fmt::print("against the recording: no step both hold the plant's output and inputs\n");
    else if (!g.apart)
      fmt::print("against the recording, step for step: y_true and u identical at all {} steps both hold\n", g.steps);
    else
      fmt::print("against the recording, step for step: {} of {} steps identical; apart from step {} on, by up to "
                 "{:.4g} in y_true and {:.4g} in u\n",
                 g.identical, g.steps, g.first_apart, g.dy, g.du);
  } catch (const DbError& e) {
    throw CliError(e.what());
  }
}

void replay(const ReplayArgs& a) {
  if (!a.svg.empty() && !a.png.empty()) throw CliError("runs replay: give --svg FILE or --png FILE, not both");
  const std::string db = a.db.empty() ? default_db_path() : a.db;
  RecordedStart start;
  try {
    RunStore store(db);
    start = recorded_start(store, a.id);
  } catch (const DbError& e) {
    throw CliError(e.what());
  }
  const RunRow& row = start.row;
  const Rig rig = replay_rig(a, row);
  if (std::lround(rig.rate_hz) != std::lround(row.loop_rate_hz))
    throw CliError(fmt::format("run {} ran at {:g} Hz, rig '{}' at {:g} Hz (a simulator started with --sim-rate): "
                               "not replayable as it ran",
                               a.id, row.loop_rate_hz, rig.name, rig.rate_hz));
  auto model = std::make_unique<LoadedModel>();
  replay_model(a, rig, *model);

  // Every change read and checked before anything runs or is recorded.
  SimulatorInProcess sim(rig, model->file, a.seed);
  p::InfoEx info;
  if (!sim.request(p::InfoGet{}).as(info)) throw CliError("the simulator in this process sent no INFO_EX");
  const bool same_model = info.info.model_hash == row.model_hash;
  if (a.model.empty() && !same_model)
    throw CliError(fmt::format("run {} ran model 0x{:08x}, not rig '{}''s shipped model {} (0x{:08x}): give --model "
                               "FILE, the model uploaded then (or another, to see what it would have done)",
                               a.id, row.model_hash, rig.name, model->path, info.info.model_hash));
  const ParamCatalog catalog = catalog_of(sim, info);
  const std::vector<std::string> changes = put_in_force(
      a, sim, catalog, start, same_model ? "" : fmt::format("model {} (0x{:08x})", model->path, info.info.model_hash));
  expect_ack(sim, ref_select_of(start.reference), "the run's reference");
  p::TelemetryConfig tc;
  tc.mask = tf::kAll;
  tc.decimation = uint16_t(std::max(row.decimation, 1));
  expect_ack(sim, tc, "TELEMETRY_CONFIG");
  const bool sensors = (info.info.capabilities & p::capability::kSensorStream) != 0;
  if (sensors) {
    p::SensorStream on;
    on.on = 1;
    expect_ack(sim, on, "SENSOR_STREAM");
  }
  // At rest, as a simulator idles at neutral before a run.
  for (long k = 0; k < std::lround(2.0 * sim.rate_hz()); ++k) sim.step();
  sim.take_frames();
  const RunInfo ri = replay_run_info(a, row, info, catalog, sim, changes, tc.decimation, sensors);

  for (const std::string& s : start.not_repeated) fmt::print("{}\n", s);
  if (row.lost_frames > 0)
    fmt::print("run {} lost {} frames: its figures are over the {} samples it holds, the replay's over every step\n",
               a.id, row.lost_frames, row.samples);

  Recorder recorder(db);
  const int64_t id = recorder.begin_run(ri);
  p::RunStart rs;
  rs.run_id = uint32_t(id);
  expect_ack(sim, rs, "RUN_START");
  const uint32_t steps = start.last_step + 1;
  ProgressBar bar(fmt::format("replay of run {}", a.id));
  const uint64_t k = record_steps(sim, recorder, id, steps, ri.w, bar);
  sim.request(p::RunStop{});
  recorder.end_run(id, "completed", k, 0);
  bar.update(long(steps), long(steps));
  bar.finish();

  fmt::print("run {}: run {} replayed on {} ({} steps at {:g} Hz, noise seed {}), {}\n", id, a.id,
             ri.firmware, steps, row.loop_rate_hz, a.seed,
             changes.empty() ? std::string("nothing changed") : "changed: " + fmt::format("{}", fmt::join(changes, "; ")));
  say_agreement(db, a.id, id);
  compare_runs(db, a.id, id, false, a.svg, a.png);
}

}  // namespace

void add_replay_command(CLI::App& runs) {
  auto a = std::make_shared<ReplayArgs>();
  CLI::App* c = runs.add_subcommand(
      "replay",
      "Run a recorded closed-loop run of the simulator again, step for step, with changes: its\n"
      "reference, parameters and model as they were at its start, then --set and --model on top;\n"
      "the simulator's own firmware and plant run here, in this process, as fast as the host\n"
      "goes. The replay is recorded as a run (kind replay) and set beside the recording as\n"
      "`runs compare` sets two runs side by side. With nothing changed it gives the recording\n"
      "back, bit for bit, and says so.\n"
      "Example: nlsoft-console runs replay 12 --set Lambda=0.5\n"
      "         nlsoft-console runs replay 12 --model retrained.nlsm --svg replay.svg");
  c->add_option("run", a->id, "the recorded run (runs list)")->required()->check(CLI::PositiveNumber)->type_name("ID");
  c->add_option("--db", a->db, "Recording database (default $XDG_DATA_HOME/nlsoft/runs.db)")->type_name("FILE");
  c->add_option("--set", a->sets, "change a parameter from its value at the run's start: NAME=V[,V...]; repeat")
      ->type_name("NAME=V");
  c->add_option("--model", a->model, "run this model instead (default: the rig's shipped model, which must be the "
                                     "run's)")
      ->type_name("FILE");
  add_rig_option(c, a->rig, "the run's rig file, for a rig that is not shipped");
  c->add_option("--seed", a->seed, "the plant's noise seed (default 1, the simulator's; a --sim run records none)")
      ->capture_default_str();
  c->add_option("--label", a->label, "the replay's label (default: \"replay of run ID\" and the first change)");
  c->add_option("--svg", a->svg, "draw the recording and the replay overlaid, as runs plot draws two runs")
      ->type_name("FILE");
  c->add_option("--png", a->png, "the same as a PNG")->type_name("FILE");
  c->callback([a] { replay(*a); });
}

}  // namespace nlsoft::console
