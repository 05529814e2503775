#include "app/live/console_command.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <memory>

#include "app/cli_error.hpp"
#include "app/link/link_error.hpp"
#include "app/link/sim_launcher.hpp"
#include "app/live/live_console.hpp"
#include "app/progress_bar.hpp"
#include "app/record/sqlite.hpp"
#include "app/script/script_runner.hpp"
#include "app/tui/tui_app.hpp"

namespace nlsoft::console {

namespace {

struct ConsoleArgs {
  std::string port, sim, qemu, script, db, udp, board = "mps2-an386";
  unsigned baud = 115200;
  bool no_record = false;
  int decimation = 0;
  double sim_rate = 0;
  bool sim_fast = false;
  int timeout_ms = 250;
  double wait_s = 0;
};

void on_interrupt(int) { LiveConsole::request_interrupt(); }

int run_console(const ConsoleArgs& a) {
  if (!a.qemu.empty() && !a.sim.empty()) throw CliError("give either --sim or --qemu, not both");
  if (a.port.empty() && a.sim.empty() && a.qemu.empty())
    throw CliError("nothing to connect to: give a serial port (nlsoft-console /dev/ttyACM0) or --sim hasel; "
                   "see nlsoft-console --help");
  if (!a.port.empty() && !(a.sim.empty() && a.qemu.empty()))
    throw CliError("give either a PORT or --sim/--qemu, not both");
  if (a.qemu.empty() && a.board != "mps2-an386") throw CliError("--board names the image --qemu boots; give --qemu too");
  Script script;
  if (!a.script.empty()) {
    // Parse everything before connecting: a typo on line 40 should not cost
    // a board session.
    try {
      script = parse_script_file(a.script);
    } catch (const ScriptError& e) {
      throw CliError(e.what());
    }
  } else if (!isatty(STDIN_FILENO) || !isatty(STDOUT_FILENO)) {
    throw CliError("the interactive console needs a terminal; for headless use give --script FILE");
  }
  LiveOptions o;
  o.port = a.port;
  o.baud = a.baud;
  o.sim_platform = a.qemu.empty() ? a.sim : a.qemu;
  o.sim_in_qemu = !a.qemu.empty();
  o.qemu_board = a.board;
  if (a.sim_rate > 0) o.sim_args.insert(o.sim_args.end(), {"--rate", fmt::format("{:g}", a.sim_rate)});
  if (a.sim_fast) o.sim_args.push_back("--fast");
  o.db_path = a.db;
  o.record = !a.no_record;
  o.decimation = a.decimation;
  o.udp = a.udp;
  o.session.timeout = std::chrono::milliseconds(a.timeout_ms);
  o.wait = a.wait_s < 0 ? std::chrono::milliseconds(-1) : std::chrono::milliseconds(int64_t(a.wait_s * 1000));
  LiveConsole console(o);
  // Ctrl-C stops the run cleanly (it stays in the database, marked
  // interrupted) instead of leaving it unfinished.
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  const bool headless = !a.script.empty();
  if (headless) console.set_notify([](const std::string& s) { std::fprintf(stderr, "%s\n", s.c_str()); });
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
  if (!headless) return run_tui(console);

  const auto info = console.device().info();
  std::fprintf(stderr, "connected: %s %u.%u.%u, n=%u m=%u, %u Hz, %zu parameters; recording to %s\n", info.firmware,
               info.fw_major, info.fw_minor, info.fw_patch, info.n, info.m, info.loop_rate_hz,
               console.device().catalog()->all().size(), console.db_path().c_str());
  if (const UdpStream* u = console.udp())
    std::fprintf(stderr, "streaming every telemetry sample to %s (UDP, one JSON object per datagram)\n",
                 u->target().c_str());
  std::unique_ptr<ProgressBar> bar;
  std::string bar_what;
  ScriptRunner runner(
      console, [](const std::string& s) { std::printf("%s\n", s.c_str()), std::fflush(stdout); },
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
  app.add_option("PORT", a->port, "Serial device of the board, e.g. /dev/ttyACM0");
  app.add_option("--sim", a->sim, "Start nlsoft-firmware-sim for this platform and connect to it")
      ->check(CLI::IsMember({"msd", "hasel", "tendon"}));
  app.add_option("--qemu", a->qemu,
                 "Boot the Cortex-M4F image (plant in the loop) in qemu-system-arm and connect to its UART")
      ->check(CLI::IsMember({"msd", "hasel", "tendon"}));
  app.add_option("--board", a->board,
                 "With --qemu: the board whose image QEMU boots, mps2-an386 (default) or stm32f4 (a Nucleo-64 "
                 "image in -M netduinoplus2)")
      ->check(CLI::IsMember(qemu_boards()));
  app.add_option("--baud", a->baud, "Baud rate, any integer the port supports (default 115200)")
      ->check(CLI::Range(50u, 20000000u));
  app.add_option("--script", a->script, "Run a script headless (no terminal needed); exit 0/1/2");
  app.add_option("--db", a->db, "Recording database (default $XDG_DATA_HOME/nlsoft/runs.db)");
  app.add_flag("--no-record", a->no_record, "Keep runs in a temporary database, deleted on exit");
  app.add_option("--decimation", a->decimation, "Telemetry every k-th control step (default: what the link carries)")
      ->check(CLI::Range(1, 65535));
  app.add_option("--sim-rate", a->sim_rate, "Control loop rate of the simulator, Hz")->check(CLI::PositiveNumber);
  app.add_flag("--sim-fast", a->sim_fast, "Let the simulator run faster than real time");
  app.add_option("--wait", a->wait_s,
                 "Wait this many seconds for a PORT that does not exist yet (a board being plugged in); -1: until Ctrl-C")
      ->check(CLI::Range(-1.0, 1e6));
  app.add_option("--udp", a->udp,
                 "Stream every telemetry sample to HOST:PORT, one JSON object per UDP datagram (PlotJuggler's UDP "
                 "server, JSON protocol, timestamp field 'timestamp'), while recording as usual");
  app.add_option("--timeout", a->timeout_ms, "Reply timeout per try, ms (3 retries follow)")->check(CLI::Range(10, 60000));
  std::string footer =
      "Connect and tune:\n"
      "  nlsoft-console --sim hasel              # no hardware: firmware simulator on a pty\n"
      "  nlsoft-console --qemu hasel             # the Cortex-M4F image in QEMU, UART on a pty\n"
      "  nlsoft-console --qemu hasel --board stm32f4   # the Nucleo-64 image in QEMU\n"
      "  nlsoft-console /dev/ttyACM0 --baud 1000000\n"
      "  nlsoft-console /dev/ttyACM0 --wait -1     # wait for the board to be plugged in\n"
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
      "  expect nrmse < 0.05\n"
      "  expect lost_frames == 0\n"
      "  sweep Q0 1e5 1e6 1e7 run 5s\n";
  app.footer(footer);
  app.callback([&app, a] {
    if (!app.get_subcommands().empty()) return;
    throw CliExit{run_console(*a)};
  });
}

}  // namespace nlsoft::console
