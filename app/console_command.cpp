#include "app/console_command.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <memory>

#include "host/files/cli_error.hpp"
#include "app/link/sim_launcher.hpp"
#include "app/live/connect_args.hpp"
#include "app/live/live_console.hpp"
#include "app/progress_bar.hpp"
#include "app/script/script_check.hpp"
#include "app/script/script_runner.hpp"
#include "app/tui/tui_app.hpp"

namespace nlsoft::console {

using host::CliError;
using host::CliExit;

namespace {

struct ConsoleArgs {
  ConnectArgs link;
  std::string script, udp;
  int decimation = 0;
  double wait_s = 0;
};

std::string error_count(size_t n) { return fmt::format("{} error{} in the script", n, n == 1 ? "" : "s"); }

int run_console(const ConsoleArgs& a) {
  LiveOptions o = live_options(a.link);
  Script script;
  if (!a.script.empty()) {
    // Parse everything before connecting: a typo on line 40 should not cost
    // a board session.
    try {
      script = parse_script_file(a.script);
    } catch (const ScriptError& e) {
      if (e.line == 0) throw CliError(e.what());  // not a script at all
      std::fprintf(stderr, "%s\n%s; nothing was run\n", e.what(), error_count(e.count).c_str());
      throw CliExit{2};
    }
  } else if (!isatty(STDIN_FILENO) || !isatty(STDOUT_FILENO)) {
    throw CliError("the interactive console needs a terminal; for headless use give --script FILE");
  }
  o.decimation = a.decimation;
  o.udp = a.udp;
  o.wait = a.wait_s < 0 ? std::chrono::milliseconds(-1) : std::chrono::milliseconds(int64_t(a.wait_s * 1000));
  LiveConsole console(o);
  install_interrupt_handlers();
  const bool headless = !a.script.empty();
  if (headless) console.notices().listen([](const std::string& s) { ProgressBar::say(s); });
  connect_with_progress(console);
  if (!headless) return run_tui(console);

  const auto info = console.device().info();
  std::fprintf(stderr, "connected: %s %u.%u.%u, rig %s, n=%u m=%u, %u Hz, %zu parameters; recording to %s\n",
               info.firmware, info.fw_major, info.fw_minor, info.fw_patch, console.device().rig_label().c_str(), info.n, info.m,
               info.loop_rate_hz,
               console.device().catalog()->all().size(), console.db_path().c_str());
  if (const UdpStream* u = console.udp())
    std::fprintf(stderr, "streaming every telemetry sample to %s (UDP, one JSON object per datagram)\n",
                 u->target().c_str());
  // Names, elements, counts and ranges against the firmware's parameter
  // list, before the first command: all or nothing.
  if (const auto errors = check_script(script, console); !errors.empty()) {
    for (const ScriptError& e : errors) std::fprintf(stderr, "%s\n", e.what());
    std::fprintf(stderr, "%s; nothing was run\n", error_count(errors.size()).c_str());
    console.disconnect();
    return 2;
  }
  std::unique_ptr<ProgressBar> bar;
  std::string bar_what;
  ScriptRunner runner(
      console, [](const std::string& s) { ProgressBar::say(s, stdout); },
      [&](const std::string& what, size_t d, size_t t) {
        if (what != bar_what) bar = std::make_unique<ProgressBar>(what), bar_what = what;
        bar->update(long(d), long(t));
        if (d >= t) bar.reset(), bar_what.clear();
      });
  const int rc = runner.run(script);
  bar.reset();
  console.disconnect();
  std::fprintf(stderr, "%d expect%s held, %d failed", runner.passed_expects(), runner.passed_expects() == 1 ? "" : "s",
               runner.failed_expects());
  if (runner.incomplete_runs() > 0)
    std::fprintf(stderr, "; %d run%s ended early", runner.incomplete_runs(), runner.incomplete_runs() == 1 ? "" : "s");
  if (runner.fruitless_tunes() > 0)
    std::fprintf(stderr, "; %d tuning session%s found nothing (every evaluation failed)", runner.fruitless_tunes(),
                 runner.fruitless_tunes() == 1 ? "" : "s");
  std::fprintf(stderr, "\n");
  return rc;
}

}  // namespace

void add_live_console(CLI::App& app) {
  auto a = std::make_shared<ConsoleArgs>();
  add_connect_options(app, a->link, "connect to");
  app.add_option("--script", a->script, "Run a script headless (no terminal needed); exit 0/1/2");
  app.add_option("--decimation", a->decimation, "Telemetry every k-th control step (default: what the link carries)")
      ->check(CLI::Range(1, 65535));
  app.add_option("--wait", a->wait_s,
                 "Wait this many seconds for a PORT that does not exist yet (a board being plugged in); -1: until Ctrl-C")
      ->check(CLI::Range(-1.0, 1e6));
  app.add_option("--udp", a->udp,
                 "Stream every telemetry sample to HOST:PORT, one JSON object per UDP datagram (PlotJuggler's UDP "
                 "server, JSON protocol, timestamp field 'timestamp'), while recording as usual");
  std::string footer =
      "Connect and tune:\n"
      "  nlsoft-console --sim hasel              # no hardware: firmware simulator on a pty\n"
      "  nlsoft-console --qemu hasel             # the Cortex-M4F image in QEMU, UART on a pty\n"
      "  nlsoft-console --qemu hasel --board stm32f4   # the Nucleo-64 image in QEMU\n"
      "  nlsoft-console --qemu hasel --board mps2-an500   # the Cortex-M7 image in QEMU\n"
      "  nlsoft-console /dev/ttyACM0 --baud 1000000\n"
      "  nlsoft-console /dev/ttyACM0 --wait -1     # wait for the board to be plugged in\n"
      "  nlsoft-console ports                      # which port is the board; without a PORT the lone one is taken\n"
      "Headless (CI): exit 0 when every expect held, 1 when one failed, 2 on an error\n"
      "  nlsoft-console --sim hasel --script tune.nls\n"
      "Recorded runs:\n"
      "  nlsoft-console runs list\n"
      "  nlsoft-console runs export 12 --csv run12.csv\n"
      "\nScript commands (also at the TUI's ':' prompt):\n";
  for (const auto& h : script_help()) footer += "  " + h + "\n";
  footer +=
      "\nExample script (hold=1: the whole Swirl, 1230 points, in 9.5 s at 130 Hz):\n"
      "  set Q 1e6 2e6 1e6\n"
      "  ref swirl scale=1 hold=1\n"
      "  run 10s label=baseline\n"
      "  expect nrmse < 0.06\n"
      "  expect lost_frames == 0\n"
      "  sweep Q0 1e5 1e6 1e7 run 5s\n";
  app.footer(footer);
  app.callback([&app, a] {
    if (!app.get_subcommands().empty()) return;
    throw CliExit{run_console(*a)};
  });
}

}  // namespace nlsoft::console
