#include "app/live/ident_command.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/files/cli_error.hpp"
#include "app/live/connect_args.hpp"
#include "app/live/ident_plan.hpp"
#include "app/live/live_console.hpp"
#include "app/progress_bar.hpp"
#include "app/record/merge_y.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

using host::CliError;
using host::CliExit;
using host::Rig;
using host::RigOutput;

namespace {

struct IdentArgs {
  ConnectArgs link;
  IdentWords words;
  std::string label;
  std::string y_from;               // --y-from FILE.csv: merged once the run is recorded
  std::optional<double> y_offset;   // --y-offset S: its clock offset, else estimated
};

int run_ident_command(const IdentArgs& a) {
  // The words are checked before a simulator starts or a board is touched.
  check_ident_words(a.words);
  const LiveOptions lo = live_options(a.link, "ident");
  LiveConsole console(lo);
  install_interrupt_handlers();
  console.notices().listen([](const std::string& s) { ProgressBar::say(s); });
  connect_with_progress(console);
  const protocol::Info info = console.device().info();
  IdentLine line;
  line.baud = lo.baud;
  line.unlimited = console.link_unlimited();
  line.sensor_health = sends_sensor_health(console.device());
  const IdentPlan plan =
      plan_ident(a.words, double(info.loop_rate_hz), info.m, info.n, info.w, line, console.known_rig());
  std::fprintf(stderr, "connected: %s %u.%u.%u (%s), %u Hz; recording to %s\n%s\n%s\n", info.firmware, info.fw_major,
               info.fw_minor, info.fw_patch, console.device().rig_label().c_str(), info.loop_rate_hz, console.db_path().c_str(),
               plan.excitation_words.c_str(), plan.line_words.c_str());
  const std::string label =
      a.label.empty() ? fmt::format("ident {} seed {} {}", a.words.signal, a.words.seed, a.words.duration) : a.label;
  RunSummary s;
  try {
    ProgressBar bar(fmt::format("ident {}", a.words.signal));
    s = console.runs().run_ident(plan.start, plan.excitation_json, label,
                          [&](size_t d, size_t t) { bar.update(long(d), long(t)); });
  } catch (...) {
    console.disconnect();
    throw;
  }
  console.disconnect();
  std::printf("run %lld: identification run, %s, %llu samples of %u steps (decimation %u), %llu lost frames; %s\n",
              static_cast<long long>(s.run_id), a.words.signal.c_str(),
              static_cast<unsigned long long>(s.metrics.samples), plan.start.duration, plan.start.decimation,
              static_cast<unsigned long long>(s.metrics.lost_frames), s.end_reason.c_str());
  std::fflush(stdout);
  if (!a.y_from.empty()) {
    // Read only now: a capture program may write the file while the run goes.
    // The run is recorded whatever the capture holds; a capture that cannot
    // be merged leaves it as it is and says how to merge it later.
    std::vector<std::string> names;
    if (const Rig* rig = console.known_rig())
      for (const RigOutput& o : rig->outputs) names.push_back(o.name);
    try {
      const MergeReport m = merge_y(console.db_path(), s.run_id, a.y_from, a.y_offset, names);
      std::printf("%s\n", merge_words(s.run_id, a.y_from, m).c_str());
    } catch (const CliError& e) {
      throw CliError(fmt::format("{}\nrun {} is recorded without the capture; once the file is right: nlsoft-console "
                                 "runs merge-y {} {}{} --db {}",
                                 e.what(), s.run_id, s.run_id, a.y_from,
                                 a.y_offset ? fmt::format(" --offset {}", *a.y_offset) : "", console.db_path()));
    }
  }
  return s.ended_early ? 1 : 0;
}

}  // namespace

void add_ident_command(CLI::App& app) {
  auto a = std::make_shared<IdentArgs>();
  CLI::App* c = app.add_subcommand(
      "ident", "Record an identification run: the firmware drives the rig's inputs open loop with an excitation "
               "signal inside their limits; u, the measured outputs and the sensors of every step go into the runs "
               "database, to train a model from");
  add_connect_options(*c, a->link, "identify");
  c->add_option("--signal", a->words.signal,
                "steps, prbs, walk (smoothed random walk), chirp or aprbs (default: PRBS whose every run of equal bits "
                "holds a new random level, so a model sees the whole range, not two levels)")
      ->check(CLI::IsMember(kIdentSignals));
  c->add_option("--duration", a->words.duration, "How long, in the firmware's control steps' time: 60s, 10min")
      ->required();
  c->add_option("--seed", a->words.seed, "Seed of the signal: the same seed drives the same inputs (default 1)");
  c->add_option("--amplitude", a->words.amplitude,
                "Fraction of each input's range the signal spans, around its neutral value (default: the rig file's "
                "[ident], else 0.8)");
  c->add_option("--band", a->words.band,
                "LO:HI in Hz: steps hold 1/HI to 1/LO s, PRBS and APRBS bits last 1/HI s with a period of at least "
                "1/LO s, the walk crosses the range in about 1/LO s smoothed at HI, the chirp sweeps LO to HI "
                "(default: the rig file's [ident], else 0.05:2, HI at most a quarter of the loop rate)");
  CLI::Option* joint =
      c->add_flag("--joint", a->words.joint, "Every input the same signal (default: one independent stream per input)");
  c->add_flag("--mixed", a->words.mixed,
              "Every input a shared signal plus its own, so the inputs move together (the common mode, a platform's "
              "height) and apart around it; not with prbs, whose +-1 leaves no room for the inputs' own (default: one "
              "independent stream per input)")
      ->excludes(joint);
  c->add_option("--decimation", a->words.decimation,
                "Record one step in N (default: every step on a simulator, else what the baud rate carries)")
      ->check(CLI::Range(1, 65535));
  c->add_option("--y-from", a->y_from,
                "FILE.csv, an external measurement of the outputs (motion capture: time,y0,y1,... or the rig's output "
                "names, time on the capture's clock), read when the run ends and merged as its measured outputs "
                "(runs merge-y)");
  c->add_option("--y-offset", a->y_offset,
                "The capture clock's offset in seconds (run time = capture time - S); default: estimated");
  c->add_option("--label", a->label, "The run's label (default \"ident SIGNAL seed N DURATION\")");
  c->footer(
      "The run is recorded as an identification run (runs list marks it; runs export gives u, the measured\n"
      "outputs as y_true and the sensors l0, l1, ...). It ends by itself after --duration; Ctrl-C stops it\n"
      "and keeps what was recorded. The link watchdog and RUN_HOLD act as in a closed-loop run.\n"
      "Exit 0 when the whole run was recorded, 1 when it ended early, 2 on an error.\n"
      "\n"
      "To train a model to track with, aprbs over the whole input range: each input sees every level of\n"
      "its range, not two. A rig file's [ident] sets the band and amplitude the words leave out (ident\n"
      "prints what it sends and where from). hasel's sets the whole range for aprbs, steps and walk:\n"
      "10 simulated minutes with train's defaults then track the Swirl at 6.0, 5.7 and 6.1 % nRMSE\n"
      "(means over five seeds; aprbs at 0.8 of the range: 7.1 %), prbs at 31 % (seed 3; app/CONSOLE.md).\n"
      "\n"
      "Example (10 simulated minutes of a rig file, well under a minute of wall time):\n"
      "  nlsoft-console ident --sim my-rig.toml --signal prbs --duration 10min --sim-fast\n"
      "  nlsoft-console runs export 1 --csv ident.csv\n"
      "With the outputs measured by a motion capture (its clock's offset estimated, or --y-offset):\n"
      "  nlsoft-console ident --sim my-rig.toml --signal prbs --duration 10min --y-from mocap.csv\n");
  c->callback([a] { throw CliExit{run_ident_command(*a)}; });
}

}  // namespace nlsoft::console
