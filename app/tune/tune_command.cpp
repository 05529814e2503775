#include "app/tune/tune_command.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <memory>

#include "host/files/cli_error.hpp"
#include "app/link/device.hpp"
#include "app/live/connect_args.hpp"
#include "app/live/live_console.hpp"
#include "app/progress_bar.hpp"
#include "app/text/duration.hpp"
#include "app/record/recorder.hpp"
#include "app/replay/replay_source.hpp"
#include "app/tune/replay_evaluator.hpp"
#include "app/tune/tuner.hpp"

namespace nlsoft::console {

using host::CliError;
using host::CliExit;

namespace {

struct TuneArgs {
  ConnectArgs link;
  int64_t replay = 0;  // --replay N: evaluate on replays of run N in this process
  std::string model;   // with --replay: the model the replays run
  std::string plant;   // with --replay: the plant model in the rig's place
  bool apply = false;
  std::vector<std::string> params, budget;
  std::string objective = "nrmse", reference, settle = "1s", window = "5s", method = "bobyqa", save;
  unsigned long seed = 1;
  double max_saturated = 0.5;
};

TuneOptions options_from(const TuneArgs& a) {
  TuneOptions o;
  try {
    for (const std::string& p : a.params) o.dims.push_back(parse_dimension(p));
    bool runs = false, time = false;
    for (const std::string& b : a.budget) (set_budget(o, b) ? runs : time) = true;
    if (time && !runs) o.budget_runs = 0;
    o.objective = a.objective;
    o.reference = a.reference;
    o.settle_s = a.settle == "0" ? 0.0 : text::parse_duration(a.settle);
    o.window_s = text::parse_duration(a.window);
    o.method = a.method;
    o.seed = a.seed;
    o.max_saturated = a.max_saturated;
    o.save = a.save;
    o.apply = a.apply;
    validate(o);
  } catch (const std::invalid_argument& e) {
    throw CliError(e.what());
  }
  return o;
}

// What the report and the progress bars go through, shared by both ways
// of evaluating.
class TuneOutput {
 public:
  TuneCallbacks callbacks() {
    TuneCallbacks cb;
    cb.out = [this](const std::string& s) {
      if (bar_) bar_->finish();
      std::printf("%s\n", s.c_str());
      std::fflush(stdout);
    };
    cb.progress = [this](const std::string& what, size_t d, size_t t) {
      if (what != bar_what_) bar_ = std::make_unique<ProgressBar>(what), bar_what_ = what;
      bar_->update(long(d), long(t));
    };
    return cb;
  }
  void done() { bar_.reset(); }

 private:
  std::unique_ptr<ProgressBar> bar_;
  std::string bar_what_;
};

int run_tune(const TuneArgs& a) {
  // Everything the words can tell is checked before a simulator starts or
  // a board is touched.
  const TuneOptions o = options_from(a);
  const LiveOptions lo = live_options(a.link, "tune");
  LiveConsole console(lo);
  // Ctrl-C ends the run in progress (kept, not scored) and the session,
  // which still saves the best set found so far.
  install_interrupt_handlers();
  console.notices().listen([](const std::string& s) { ProgressBar::say(s); });
  connect_with_progress(console);
  const auto info = console.device().info();
  std::fprintf(stderr, "connected: %s %u.%u.%u, %u Hz; recording to %s\n", info.firmware, info.fw_major, info.fw_minor,
               info.fw_patch, info.loop_rate_hz, console.db_path().c_str());
  TuneOutput output;
  TuneResult r;
  try {
    r = run_tuning(console, o, output.callbacks());
  } catch (...) {
    output.done();
    console.disconnect();
    throw;
  }
  output.done();
  console.disconnect();
  return r.have_best ? 0 : 1;
}

// The options that reach a firmware, refused beside --replay, which
// reaches none: named as given, so the error says what to leave out.
void refuse_connection_options(const CLI::App& t, const TuneArgs& a) {
  std::vector<std::string> given;
  if (!a.link.target.port.empty()) given.push_back(fmt::format("PORT ({})", a.link.target.port));
  for (const char* name : {"--sim", "--qemu", "--board", "--baud", "--sim-rate", "--sim-fast", "--sim-settings",
                           "--timeout", "--db-busy"})
    if (t.get_option(name)->count() > 0) given.push_back(name);
  if (!given.empty())
    throw CliError(fmt::format("tune: --replay {} evaluates each candidate on a replay of run {} in this process and "
                               "connects to nothing: leave out {}",
                               a.replay, a.replay, fmt::join(given, ", ")));
  if (t.get_option("--reference")->count() > 0)
    throw CliError(fmt::format("tune: --replay {} replays run {}'s own reference; --reference selects one on a "
                               "connected firmware: leave it out",
                               a.replay, a.replay));
  if (a.apply)
    throw CliError(fmt::format("tune: --apply leaves the best in force on a connected firmware; --replay {} has none "
                               "(the best is saved with --save and loads with params load)",
                               a.replay));
}

int run_replay_tune(const CLI::App& t, const TuneArgs& a) {
  TuneOptions o = options_from(a);
  refuse_connection_options(t, a);
  // Run N read and checked as `runs replay` checks it, the window fitted
  // to it, the evaluator set up: every refusal before a replay runs.
  const std::string db = a.link.db.empty() ? default_db_path() : a.link.db;
  const ReplaySource src = open_replay_source(db, a.replay, a.link.rig, a.model, true, a.plant);
  o.window_given = t.get_option("--window")->count() > 0;
  fit_window_to_run(src, o);
  ReplayEvaluator evaluator(src, o, !a.link.no_record);
  install_interrupt_handlers();
  const std::string recording = a.link.no_record ? "nothing recorded" : "the best recorded to " + db;
  std::fprintf(stderr, "%s\n",
               fmt::format("run {} ({}, {} steps at {:g} Hz) replayed per candidate in this process; {}", a.replay,
                           src.start.row.platform, src.steps(), src.start.row.loop_rate_hz, recording)
                   .c_str());
  for (const std::string& s : src.start.not_repeated) std::printf("%s\n", s.c_str());
  TuneOutput output;
  TuneResult r;
  try {
    r = run_tuning(evaluator, o, output.callbacks());
  } catch (...) {
    output.done();
    throw;
  }
  output.done();
  return r.have_best ? 0 : 1;
}

int run_tune(const CLI::App& t, const TuneArgs& a) {
  if (a.replay > 0) return run_replay_tune(t, a);
  if (!a.model.empty())
    throw CliError("tune: --model names the model replays run; it goes with --replay N (a connected firmware runs "
                   "the model it holds: model upload)");
  if (!a.plant.empty())
    throw CliError("tune: --plant names the plant model replays step in the rig's place; it goes with --replay N");
  return run_tune(a);
}

}  // namespace

void add_tune_command(CLI::App& app) {
  auto a = std::make_shared<TuneArgs>();
  CLI::App* t = app.add_subcommand(
      "tune", "Search controller parameters (Q, Lambda, s, b, r, ...) for the lowest objective, one real run per "
              "evaluation (or, with --replay N, one replay of recorded run N in this process); print and save the best "
              "set");
  add_connect_options(*t, a->link, "tune");
  t->add_option("--replay", a->replay,
                "Evaluate each candidate on a replay of recorded run N (runs list) in this process, through the "
                "simulator's own firmware and plant, instead of a run on a firmware: no PORT, --sim or --qemu; N must "
                "be a closed-loop run of the simulator (or, with --plant, of a board), as for runs replay; --db is where it is, --rig FILE its rig file "
                "for a rig that is not shipped")
      ->check(CLI::PositiveNumber)
      ->type_name("N");
  t->add_option("--model", a->model,
                "With --replay: the model the replays run (default: the rig's shipped model, which must be run N's)")
      ->type_name("FILE");
  t->add_option("--plant", a->plant,
                "With --replay: step this plant model in the rig's place (train --plant), as runs replay --plant "
                "does; how a board's run is tuned on")
      ->type_name("FILE");
  t->add_option("--param", a->params,
                "NAME=LO..HI[:log|:lin], once per searched dimension: Lambda=0.01..100:log (every element), Q1=1e5..1e7:log "
                "(one element), Q*=0.1..1000:log (a factor on all of Q, keeping its proportions); :log searches uniformly in the "
                "logarithm, :lin (the default) in the value; quote it in a shell: 'Q*=0.1..1000:log'")
      ->required();
  t->add_option("--objective", a->objective,
                "Expression to minimise over run metrics, e.g. \"nrmse + 0.1*u_effort\" (default nrmse); metrics: "
                "those of expect, plus u_effort (RMS input change per step over the input range) and u_saturated");
  t->add_option("--budget", a->budget, "Runs (40, the default) and/or wall time (10min); give it twice for both");
  t->add_option("--reference", a->reference, "Select this reference preset first (swirl, infinity, ...); default: the one in force");
  t->add_option("--settle", a->settle, "Each run settles this long before it is measured (default 1s)");
  t->add_option("--window", a->window, "... and is measured over this window (default 5s; with --replay: up to the end of the run)");
  t->add_option("--seed", a->seed, "Seed of NLopt's random numbers (default 1)");
  t->add_option("--method", a->method, "bobyqa (default) or neldermead")->check(CLI::IsMember({"bobyqa", "neldermead"}));
  t->add_option("--max-saturated", a->max_saturated,
                "A run whose inputs sit at a limit for more than this share of the actuator-time scores as failed (default 0.5)")
      ->check(CLI::Range(0.0, 1.0));
  t->add_option("--save", a->save, "Write the best set here with params save (default tune-SESSION.params; with --replay, tune-replay-N.params)");
  t->add_flag("--apply", a->apply, "Leave the best set in force on the firmware (default: put the old values back)");
  t->footer(
      "Each evaluation is a recorded run (label \"tune S #k\"): the reference restarted from its first point,\n"
      "--settle to settle, the objective over --window. A run that trips the watchdog, loses a frame or\n"
      "holds u at a limit too long scores as failed. Ctrl-C stops and keeps the best.\n"
      "Exit 0 with a best set saved, 1 when every evaluation failed, 2 on an error.\n"
      "\n"
      "Example (the simulated tendon rig, the whole Swirl per run, 12 runs, a second or two):\n"
      "  nlsoft-console tune --sim tendon --sim-fast --param 'Lambda=0.01..1e10:log' --param 'Q*=0.01..1e4:log' \\\n"
      "      --objective \"nrmse + 0.1*u_effort\" --budget 12 --reference \"swirl hold=1\" --settle 500ms --window 9s\n"
      "Then:\n"
      "  nlsoft-console runs list                      # the session's runs, grouped\n"
      "  nlsoft-console runs plot --tune 1 --svg t.svg # objective vs evaluation\n"
      "The same from a script or the TUI's ':' line:\n"
      "  tune Lambda=0.01..1e10:log Q*=0.01..1e4:log objective=\"nrmse + 0.1*u_effort\" budget=40\n"
      "\n"
      "--replay N: no rig, no port. Each candidate is recorded run N again, in this process (the simulator's\n"
      "firmware and plant, its reference, model and parameters at its start, the candidate on top), scored\n"
      "from --settle to the end of the run (or over --window); the search, objective, budget and lines are\n"
      "the same. The candidates' replays are not recorded: the best is replayed once more and recorded as a\n"
      "run of kind replay (none with --no-record), its set saved (default tune-replay-N.params), and its\n"
      "nrmse, u_effort and u_saturated set beside run N's. The figures are the simulator's plant, not the\n"
      "rig's. Run N must be a closed-loop run of the simulator (runs replay's rules); --reference and\n"
      "--apply have nothing to act on there, and are refused.\n"
      "  nlsoft-console tune --replay 12 --param 'Q*=0.01..1e4:log' --param 'Lambda=0.01..1e10:log'\n");
  t->callback([a, t] { throw CliExit{run_tune(*t, *a)}; });
}

}  // namespace nlsoft::console
