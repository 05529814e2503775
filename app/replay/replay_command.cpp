#include "app/replay/replay_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>

#include "app/progress_bar.hpp"
#include "app/record/recorder.hpp"
#include "app/record/run_metrics.hpp"
#include "app/record/run_store.hpp"
#include "app/record/runs_command.hpp"
#include "app/replay/pid_replay.hpp"
#include "app/replay/replay_run.hpp"
#include "app/replay/replay_source.hpp"
#include "host/files/cli_error.hpp"
#include "host/rig/rig_option.hpp"

namespace nlsoft::console {

using host::CliError;
using host::add_rig_option;

namespace {

struct ReplayArgs {
  int64_t id = 0;
  std::string db, rig, model, plant, label, svg, png, controller = "mpc";
  std::vector<std::string> sets;
  uint32_t seed = 1;
};

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

// --set's on top of the run's parameters; what differs from the run, in
// words (the model first when it is another).
std::vector<std::string> put_in_force(const ReplayArgs& a, ReplayRun& replay) {
  std::vector<std::string> changes;
  if (!replay.other_model().empty()) changes.push_back(replay.other_model());
  for (const std::string& s : a.sets) {
    const size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size())
      throw CliError(fmt::format("--set {}: give NAME=VALUE (Q=1e6,2e6,1e6; Lambda=0.5)", s));
    const ParamInfo& pi = replay.catalog().require(s.substr(0, eq));
    replay.set(pi, s.substr(eq + 1), "--set " + s);
    changes.push_back(s);
  }
  return changes;
}

std::string replay_label(const ReplayArgs& a, const std::vector<std::string>& changes) {
  return !a.label.empty() ? a.label
                          : fmt::format("replay of run {}{}", a.id,
                                        changes.empty() ? "" : ": " + changes.front() + (changes.size() > 1 ? ", ..." : ""));
}

std::string replay_notes(const ReplayArgs& a, const std::vector<std::string>& changes) {
  return fmt::format("runs replay {} ({}){}", a.id, a.plant.empty() ? fmt::format("noise seed {}", a.seed) : "plant model " + a.plant,
                     changes.empty() ? std::string(", nothing changed")
                                     : ", changed: " + fmt::format("{}", fmt::join(changes, "; ")));
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

// What stands in for the rig, in a few words: the simulator's plant and
// its noise seed, or a plant model.
std::string plant_words(const ReplayArgs& a, const ReplaySource& src) {
  return src.plant ? "plant model " + src.plant_path : fmt::format("noise seed {}", a.seed);
}

// A plant model, and how far to trust it, said before the replay runs.
void say_plant(const ReplayArgs& a, const ReplaySource& src) {
  if (!src.plant) return;
  fmt::print("the plant is the plant model {} (rig {}, {} parts), not the rig: started at run {}'s first sample, "
             "no noise; how far to trust it, its {}\n",
             src.plant_path, src.plant->rig, src.plant->parts.size(), a.id, src.plant->fit);
}

// The plant model on run `src` with nothing changed, replayed into a scratch
// database: its nRMSE, the plant's own error on this very run, which the
// replay's figures are to be set against (not recorded).
double unchanged_nrmse(const ReplaySource& src, uint32_t seed) {
  char tmpl[] = "/tmp/nlsoft-replay-XXXXXX";
  if (!::mkdtemp(tmpl)) throw CliError(fmt::format("cannot create a scratch database: {}", std::strerror(errno)));
  const std::string dir = tmpl, db = dir + "/unchanged.db";
  double nrmse = std::nan("");
  try {
    int64_t id = 0;
    {
      ReplayRun run(src, seed);
      run.prepare();
      Recorder recorder(db);
      id = recorder.begin_run(run.run_info("unchanged", ""));
      run.record(recorder, id);
    }
    RunStore store(db);
    nrmse = metric_value(run_metrics(store, id), "nrmse").value_or(std::nan(""));
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    throw;
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return nrmse;
}

// --controller pid: the rig's PID baseline on the run's reference, offline
// (pid_replay.hpp); nothing of the MPC's is changed, so --set and --model
// have nothing to act on.
void replay_with_pid(const ReplayArgs& a, const std::string& db) {
  if (!a.model.empty() || !a.sets.empty())
    throw CliError(fmt::format("runs replay --controller pid: {} changes the MPC, which a PID replay does not run "
                               "(its gains are the rig file's [pid])",
                               !a.model.empty() ? "--model" : "--set"));
  const ReplaySource src = open_replay_source(db, a.id, a.rig, "", false, a.plant);
  const RunRow& row = src.start.row;
  for (const std::string& s : src.start.not_repeated) fmt::print("{}\n", s);
  say_plant(a, src);
  Recorder recorder(db);
  ProgressBar bar(fmt::format("PID replay of run {}", a.id));
  const PidReplay r =
      record_pid_replay(src, a.seed, a.label.empty() ? fmt::format("replay of run {}: controller pid", a.id) : a.label,
                        fmt::format("runs replay {} --controller pid ({})", a.id, plant_words(a, src)), recorder,
                        [&](long done, long total) { bar.update(done, total); });
  bar.finish();
  recorder.flush();
  fmt::print("run {}: run {}'s reference through rig {}'s PID baseline ({}), {} steps at {:g} Hz, {}: "
             "the offline loop of simulate --controller pid, not the firmware\n",
             r.id, a.id, src.rig.name, r.gains, r.samples, row.loop_rate_hz, plant_words(a, src));
  compare_runs(db, a.id, r.id, false, a.svg, a.png);
}

void replay(const ReplayArgs& a) {
  if (!a.svg.empty() && !a.png.empty()) throw CliError("runs replay: give --svg FILE or --png FILE, not both");
  const std::string db = a.db.empty() ? default_db_path() : a.db;
  if (a.controller == "pid") return replay_with_pid(a, db);
  const ReplaySource src = open_replay_source(db, a.id, a.rig, a.model, true, a.plant);
  const RunRow& row = src.start.row;

  // Every change read and checked before anything runs or is recorded.
  ReplayRun replay(src, a.seed);
  const std::vector<std::string> changes = put_in_force(a, replay);
  replay.prepare();
  const RunInfo ri = replay.run_info(replay_label(a, changes), replay_notes(a, changes));

  for (const std::string& s : src.start.not_repeated) fmt::print("{}\n", s);
  say_plant(a, src);
  if (row.lost_frames > 0)
    fmt::print("run {} lost {} frames: its figures are over the {} samples it holds, the replay's over every step\n",
               a.id, row.lost_frames, row.samples);

  Recorder recorder(db);
  const int64_t id = recorder.begin_run(ri);
  const uint32_t steps = src.steps();
  ProgressBar bar(fmt::format("replay of run {}", a.id));
  replay.record(recorder, id, [&](size_t done, size_t total) { bar.update(long(done), long(total)); });
  bar.finish();

  fmt::print("run {}: run {} replayed on {} ({} steps at {:g} Hz, {}), {}\n", id, a.id, ri.firmware, steps,
             row.loop_rate_hz, plant_words(a, src),
             changes.empty() ? std::string("nothing changed") : "changed: " + fmt::format("{}", fmt::join(changes, "; ")));
  say_agreement(db, a.id, id);
  compare_runs(db, a.id, id, false, a.svg, a.png);
  // A plant model's own error on this run, beside what it replayed: the
  // change is what moves the replay away from the plant's unchanged replay.
  if (src.plant && !changes.empty()) {
    const double unchanged = unchanged_nrmse(src, a.seed);
    RunStore store(db);
    const double recorded = metric_value(run_metrics(store, a.id), "nrmse").value_or(std::nan(""));
    fmt::print("through the plant model with nothing changed, run {} tracks at nrmse {:.4g} against the {:.4g} it "
               "recorded: set the replay's figures against the former (the plant model's own error on this run)\n",
               a.id, unchanged, recorded);
  }
}

}  // namespace

void add_replay_command(CLI::App& runs) {
  auto a = std::make_shared<ReplayArgs>();
  CLI::App* c = runs.add_subcommand(
      "replay",
      "Run a recorded closed-loop run again, step for step, with changes: its reference,\n"
      "parameters and model as they were at its start, then --set and --model on top; the\n"
      "simulator's own firmware and plant run here, in this process, as fast as the host goes.\n"
      "A board's run steps a plant model in the rig's place (--plant, from train --plant), whose\n"
      "own fit is said first. The replay is recorded as a run (kind replay) and set beside the\n"
      "recording as `runs compare` sets two runs side by side. A simulator's run with nothing\n"
      "changed comes back bit for bit, and it says so.\n"
      "Example: nlsoft-console runs replay 12 --set Lambda=0.5\n"
      "         nlsoft-console runs replay 12 --model retrained.nlsm --svg replay.svg\n"
      "         nlsoft-console runs replay 12 --controller pid   (what the PID baseline would have done)\n"
      "A board's: nlsoft-console train --rig hasel --run 3 --run 12 --plant --out hasel.nlsp\n"
      "         nlsoft-console runs replay 12 --plant hasel.nlsp --set Lambda=0.5");
  c->add_option("run", a->id, "the recorded run (runs list)")->required()->check(CLI::PositiveNumber)->type_name("ID");
  c->add_option("--db", a->db, "Recording database (default $XDG_DATA_HOME/nlsoft/runs.db)")->type_name("FILE");
  c->add_option("--set", a->sets, "change a parameter from its value at the run's start: NAME=V[,V...]; repeat")
      ->type_name("NAME=V");
  c->add_option("--model", a->model, "run this model instead (default: the rig's shipped model, which must be the "
                                     "run's)")
      ->type_name("FILE");
  add_rig_option(c, a->rig, "the run's rig file, for a rig that is not shipped");
  c->add_option("--plant", a->plant,
                "step this plant model in the rig's place (train --rig R --run ID... --plant --out FILE): how\n"
                "a board's or QEMU image's run replays; a simulator's run too, to see how near the model comes")
      ->type_name("FILE");
  c->add_option("--seed", a->seed, "the plant's noise seed (default 1, the simulator's; a --sim run records none)")
      ->capture_default_str();
  c->add_option("--controller", a->controller,
                "mpc: the recorded controller, as it ran; pid: the rig file's PID baseline ([pid]) on the run's "
                "reference instead, offline, as simulate --controller pid runs it")
      ->check(CLI::IsMember({"mpc", "pid"}))
      ->capture_default_str();
  c->add_option("--label", a->label, "the replay's label (default: \"replay of run ID\" and the first change)");
  c->add_option("--svg", a->svg, "draw the recording and the replay overlaid, as runs plot draws two runs")
      ->type_name("FILE");
  c->add_option("--png", a->png, "the same as a PNG")->type_name("FILE");
  c->callback([a] { replay(*a); });
}

}  // namespace nlsoft::console
