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
#include "app/tune/tuner.hpp"

namespace nlsoft::console {

namespace {

struct TuneArgs {
  ConnectArgs link;
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
  add_connect_options(*t, a->link, "tune");
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
      "  nlsoft-console tune --sim tendon --sim-fast --param 'Lambda=0.01..1e10:log' --param 'Q*=0.01..1e4:log' \\\n"
      "      --objective \"nrmse + 0.1*u_effort\" --budget 12 --reference \"swirl hold=1\" --settle 500ms --window 9s\n"
      "Then:\n"
      "  nlsoft-console runs list                      # the session's runs, grouped\n"
      "  nlsoft-console runs plot --tune 1 --svg t.svg # objective vs evaluation\n"
      "The same from a script or the TUI's ':' line:\n"
      "  tune Lambda=0.01..1e10:log Q*=0.01..1e4:log objective=\"nrmse + 0.1*u_effort\" budget=40\n");
  t->callback([a] { throw CliExit{run_tune(*a)}; });
}

}  // namespace nlsoft::console
