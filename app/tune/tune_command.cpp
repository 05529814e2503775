#include "app/tune/tune_command.hpp"

#include <fmt/format.h>

#include <csignal>
#include <cstdio>
#include <memory>

#include "app/cli_error.hpp"
#include "app/link/device.hpp"
#include "app/link/link_error.hpp"
#include "app/live/live_console.hpp"
#include "app/progress_bar.hpp"
#include "app/record/sqlite.hpp"
#include "app/script/script_parser.hpp"
#include "app/tune/tuner.hpp"

namespace nlsoft::console {

namespace {

struct TuneArgs {
  std::string port, sim, qemu, db;
  unsigned baud = 115200;
  bool no_record = false, sim_fast = false, apply = false;
  double sim_rate = 0;
  int timeout_ms = 250;
  std::vector<std::string> params, budget;
  std::string objective = "nrmse", reference, settle = "1s", window = "5s", method = "bobyqa", save;
  unsigned long seed = 1;
  double max_saturated = 0.5;
};

void on_interrupt(int) { LiveConsole::request_interrupt(); }

TuneOptions options_from(const TuneArgs& a) {
  TuneOptions o;
  try {
    for (const std::string& p : a.params) o.dims.push_back(parse_dimension(p));
    bool runs = false, time = false;
    for (const std::string& b : a.budget) (set_budget(o, b) ? runs : time) = true;
    if (time && !runs) o.budget_runs = 0;
    o.objective = a.objective;
    o.reference = a.reference;
    o.settle_s = a.settle == "0" ? 0.0 : parse_duration(a.settle);
    o.window_s = parse_duration(a.window);
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

int run_tune(const TuneArgs& a) {
  // Everything the words can tell is checked before a simulator starts or
  // a board is touched.
  const TuneOptions o = options_from(a);
  if (!a.qemu.empty() && !a.sim.empty()) throw CliError("tune: give either --sim or --qemu, not both");
  if (a.port.empty() && a.sim.empty() && a.qemu.empty())
    throw CliError("tune: nothing to connect to: give a serial port or --sim hasel; see nlsoft-console tune --help");
  if (!a.port.empty() && !(a.sim.empty() && a.qemu.empty()))
    throw CliError("tune: give either a PORT or --sim/--qemu, not both");
  LiveOptions lo;
  lo.port = a.port;
  lo.baud = a.baud;
  lo.sim_platform = a.qemu.empty() ? a.sim : a.qemu;
  lo.sim_in_qemu = !a.qemu.empty();
  if (a.sim_rate > 0) lo.sim_args.insert(lo.sim_args.end(), {"--rate", fmt::format("{:g}", a.sim_rate)});
  if (a.sim_fast) lo.sim_args.push_back("--fast");
  lo.db_path = a.db;
  lo.record = !a.no_record;
  lo.session.timeout = std::chrono::milliseconds(a.timeout_ms);
  LiveConsole console(lo);
  // Ctrl-C ends the run in progress (kept, not scored) and the session,
  // which still saves the best set found so far.
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  console.set_notify([](const std::string& s) { std::fprintf(stderr, "%s\n", s.c_str()); });
  try {
    ProgressBar bar("parameters");
    console.connect([&](size_t d, size_t t) { bar.update(long(d), long(t)); });
  } catch (const LinkError& e) {
    throw CliError(e.what());
  } catch (const NackError& e) {
    throw CliError(e.what());
  } catch (const DbError& e) {
    throw CliError(e.what());
  }
  const auto info = console.device().info();
  std::fprintf(stderr, "connected: %s %u.%u.%u, %u Hz; recording to %s\n", info.firmware, info.fw_major, info.fw_minor,
               info.fw_patch, info.loop_rate_hz, console.db_path().c_str());
  std::unique_ptr<ProgressBar> bar;
  std::string bar_what;
  TuneCallbacks cb;
  cb.out = [&](const std::string& s) {
    if (bar) bar->finish();
    std::printf("%s\n", s.c_str());
    std::fflush(stdout);
  };
  cb.progress = [&](const std::string& what, size_t d, size_t t) {
    if (what != bar_what) bar = std::make_unique<ProgressBar>(what), bar_what = what;
    bar->update(long(d), long(t));
  };
  TuneResult r;
  try {
    r = run_tuning(console, o, cb);
  } catch (...) {
    bar.reset();
    console.disconnect();
    throw;
  }
  bar.reset();
  console.disconnect();
  return r.have_best ? 0 : 1;
}

}  // namespace

void add_tune_command(CLI::App& app) {
  auto a = std::make_shared<TuneArgs>();
  CLI::App* t = app.add_subcommand(
      "tune", "Search controller parameters (Q, Lambda, s, b, r, ...) for the lowest objective, one real run per "
              "evaluation; print and save the best set");
  t->add_option("PORT", a->port, "Serial device of the board, e.g. /dev/ttyACM0");
  t->add_option("--sim", a->sim, "Tune nlsoft-firmware-sim for this platform")->check(CLI::IsMember({"msd", "hasel", "tendon"}));
  t->add_option("--qemu", a->qemu, "Tune the Cortex-M4F image in qemu-system-arm")
      ->check(CLI::IsMember({"msd", "hasel", "tendon"}));
  t->add_option("--baud", a->baud, "Baud rate (default 115200)")->check(CLI::Range(50u, 20000000u));
  t->add_flag("--sim-fast", a->sim_fast, "Let the simulator run faster than real time");
  t->add_option("--sim-rate", a->sim_rate, "Control loop rate of the simulator, Hz")->check(CLI::PositiveNumber);
  t->add_option("--db", a->db, "Recording database (default $XDG_DATA_HOME/nlsoft/runs.db)");
  t->add_flag("--no-record", a->no_record, "Keep the runs in a temporary database, deleted on exit");
  t->add_option("--timeout", a->timeout_ms, "Reply timeout per try, ms")->check(CLI::Range(10, 60000));
  t->add_option("--param", a->params,
                "NAME=LO..HI[:log], once per searched dimension: Lambda=0.01..100:log (every element), Q1=1e5..1e7:log "
                "(one element), Q*=0.1..1000:log (a factor on all of Q, keeping its proportions)")
      ->required();
  t->add_option("--objective", a->objective,
                "Expression to minimise over run metrics, e.g. \"nrmse + 0.1*u_effort\" (default nrmse); metrics: "
                "those of expect, plus u_effort (RMS input change per step over the input range) and u_saturated");
  t->add_option("--budget", a->budget, "Runs (40, the default) and/or wall time (10min); give it twice for both");
  t->add_option("--reference", a->reference, "Select this reference preset first (swirl, infinity, ...); default: the one in force");
  t->add_option("--settle", a->settle, "Each run settles this long before it is measured (default 1s)");
  t->add_option("--window", a->window, "... and is measured over this window (default 5s)");
  t->add_option("--seed", a->seed, "Seed of NLopt's random numbers (default 1)");
  t->add_option("--method", a->method, "bobyqa (default) or neldermead")->check(CLI::IsMember({"bobyqa", "neldermead"}));
  t->add_option("--max-saturated", a->max_saturated,
                "A run whose inputs sit at a limit for more than this share of the actuator-time scores as failed (default 0.5)")
      ->check(CLI::Range(0.0, 1.0));
  t->add_option("--save", a->save, "Write the best set here with params save (default tune-SESSION.params)");
  t->add_flag("--apply", a->apply, "Leave the best set in force on the firmware (default: put the old values back)");
  t->footer(
      "Each evaluation is a recorded run (label \"tune S #k\"): the reference restarted from its first point,\n"
      "--settle to settle, the objective over --window. A run that trips the watchdog, loses a frame or\n"
      "holds u at a limit too long scores as failed. Ctrl-C stops and keeps the best.\n"
      "Exit 0 with a best set saved, 1 when every evaluation failed, 2 on an error.\n"
      "\n"
      "Example (the simulated tendon rig, the whole Swirl per run, 12 runs, a second or two):\n"
      "  nlsoft-console tune --sim tendon --sim-fast --param Lambda=0.01..1e10:log --param Q*=0.01..1e4:log \\\n"
      "      --objective \"nrmse + 0.1*u_effort\" --budget 12 --reference \"swirl hold=1\" --settle 500ms --window 9s\n"
      "Then:\n"
      "  nlsoft-console runs list                      # the session's runs, grouped\n"
      "  nlsoft-console runs plot --tune 1 --svg t.svg # objective vs evaluation\n"
      "The same from a script or the TUI's ':' line:\n"
      "  tune Lambda=0.01..1e10:log Q*=0.01..1e4:log objective=\"nrmse + 0.1*u_effort\" budget=40\n");
  t->callback([a] { throw CliExit{run_tune(*a)}; });
}

}  // namespace nlsoft::console
