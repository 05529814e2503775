#include "app/live/connect_args.hpp"

#include <fmt/format.h>

#include <csignal>

#include "app/cli_error.hpp"
#include "app/link/link_error.hpp"
#include "app/link/sim_launcher.hpp"
#include "app/progress_bar.hpp"
#include "app/record/sqlite.hpp"

namespace nlsoft::console {

namespace {

void on_interrupt(int signal) { LiveConsole::request_interrupt(signal); }

}  // namespace

void add_connect_options(CLI::App& app, ConnectArgs& a, const std::string& what) {
  app.add_option("PORT", a.port, "Serial device of the board, e.g. /dev/ttyACM0");
  app.add_option("--sim", a.sim, fmt::format("Start nlsoft-firmware-sim for this platform and {} it", what))
      ->check(CLI::IsMember({"msd", "hasel", "tendon"}));
  app.add_option("--qemu", a.qemu,
                 fmt::format("Boot the Cortex-M4F image (plant in the loop) in qemu-system-arm and {} it", what))
      ->check(CLI::IsMember({"msd", "hasel", "tendon"}));
  app.add_option("--board", a.board,
                 "With --qemu: the board whose image QEMU boots, mps2-an386 (default) or stm32f4 (a Nucleo-64 "
                 "image in -M netduinoplus2)")
      ->check(CLI::IsMember(qemu_boards()));
  app.add_option("--baud", a.baud, "Baud rate, any integer the port supports (default 115200)")
      ->check(CLI::Range(50u, 20000000u));
  app.add_option("--db", a.db, "Recording database (default $XDG_DATA_HOME/nlsoft/runs.db)");
  app.add_flag("--no-record", a.no_record, "Keep runs in a temporary database, deleted on exit");
  app.add_option("--sim-rate", a.sim_rate, "Control loop rate of the simulator, Hz")->check(CLI::PositiveNumber);
  app.add_flag("--sim-fast", a.sim_fast, "Let the simulator run faster than real time");
  app.add_option("--timeout", a.timeout_ms, "Reply timeout per try, ms (3 retries follow)")->check(CLI::Range(10, 60000));
}

LiveOptions live_options(const ConnectArgs& a, const std::string& command) {
  const std::string who = command.empty() ? "" : command + ": ";
  const std::string cmd = command.empty() ? "" : command + " ";
  if (!a.qemu.empty() && !a.sim.empty()) throw CliError(who + "give either --sim or --qemu, not both");
  if (a.port.empty() && a.sim.empty() && a.qemu.empty())
    throw CliError(fmt::format("{}nothing to connect to: give a serial port (nlsoft-console {}/dev/ttyACM0) or --sim "
                               "hasel; see nlsoft-console {}--help",
                               who, cmd, cmd));
  if (!a.port.empty() && !(a.sim.empty() && a.qemu.empty()))
    throw CliError(who + "give either a PORT or --sim/--qemu, not both");
  if (a.qemu.empty() && a.board != "mps2-an386")
    throw CliError(who + "--board names the image --qemu boots; give --qemu too");
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
  o.session.timeout = std::chrono::milliseconds(a.timeout_ms);
  return o;
}

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  // A closed terminal (SIGHUP) or a reader of standard output gone (SIGPIPE:
  // `ssh host nlsoft-console --script ...` dropped) would otherwise kill the
  // console mid-run and leave the run unfinished.
  for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaction(signal, &sa, nullptr);
}

void connect_with_progress(LiveConsole& console) {
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
}

}  // namespace nlsoft::console
