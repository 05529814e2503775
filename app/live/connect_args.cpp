#include "app/live/connect_args.hpp"

#include <fmt/format.h>

#include <csignal>
#include <cstdio>

#include "host/files/cli_error.hpp"
#include "app/link/link_error.hpp"
#include "app/live/interrupt.hpp"
#include "app/link/serial_ports.hpp"
#include "app/progress_bar.hpp"
#include "app/record/recorder.hpp"
#include "app/record/sqlite.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_option.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::add_rig_option;
using host::rig_arg_help;

namespace {

void on_interrupt(int signal) { request_interrupt(signal); }

// No PORT, --sim or --qemu: the one port that looks like a board (or the
// only port there is) is taken, and named; none or several is an error
// that lists what was found.
std::string pick_port(const std::string& who, const std::string& cmd) {
  const PortRoots roots = PortRoots::from_environment();
  const std::vector<SerialPort> found = list_serial_ports(roots);
  const std::vector<SerialPort> c = candidate_ports(found);
  if (c.size() == 1) {
    std::fprintf(stderr, "nlsoft-console: no port given; connecting to the only %s: %s (%s)\n",
                 c.front().board.empty() ? "serial port" : "board found", c.front().path.c_str(),
                 describe_port(c.front()).c_str());
    return c.front().path;
  }
  if (c.empty())
    throw CliError(fmt::format("{}nothing to connect to: no serial port found (looked in {} and {}/class/tty); give a "
                               "serial port (nlsoft-console {}/dev/ttyACM0) or --sim hasel; see nlsoft-console {}--help",
                               who, roots.by_id, roots.sysfs, cmd, cmd));
  std::string list;
  for (const SerialPort& p : c) list += fmt::format("\n  {}  ({})", p.path, describe_port(p));
  throw CliError(fmt::format("{}nothing to connect to: {} ports could be the board, give one (nlsoft-console {}PORT):{}",
                             who, c.size(), cmd, list));
}

// --sim's settings flash (PROTOCOL.md 9.11): one file per rig beside the
// recording database (<db>.RIG.settings, as <db>.session.log), so what
// `settings save` keeps survives the console and the simulator, and a
// database of its own (a test's, another lab's) has settings of its own;
// none under --no-record, which keeps nothing; "none": none either.
std::string sim_settings_file(const ConnectArgs& a, const Rig& rig, const std::string& who) {
  if (a.sim_settings == "none") return "";
  if (!a.sim_settings.empty()) return a.sim_settings;
  if (a.no_record) return "";
  std::string name = rig.name;
  for (char& ch : name)
    if (ch == '/' || ch == '\\' || ch == ' ') ch = '_';
  const std::string path = (a.db.empty() ? default_db_path() : a.db) + "." + name + ".settings";
  try {
    ensure_parent_dir(path);
  } catch (const std::exception& e) {
    throw CliError(fmt::format("{}--sim: no folder for the simulator's settings: {}; give --sim-settings FILE or "
                               "--sim-settings none",
                               who, e.what()));
  }
  return path;
}

}  // namespace

void add_connect_options(CLI::App& app, ConnectArgs& a, const std::string& what) {
  add_target_options(app, a.target,
                     "Serial device of the board, e.g. /dev/ttyACM0; without PORT, --sim or --qemu: the one board "
                     "`nlsoft-console ports` finds",
                     what);
  add_rig_option(&app, a.rig,
                 fmt::format("With PORT: the rig file the board's image was built from, {}: references and "
                             "defaults come from it, and the console warns when the firmware names another rig or "
                             "rig hash (default: the shipped rig the firmware names; --sim and --qemu take their "
                             "rig from their own argument)",
                             rig_arg_help()));
  app.add_option("--baud", a.baud, "Baud rate, any integer the port supports (default 115200)")
      ->check(CLI::Range(50u, 20000000u));
  app.add_option("--db", a.db, "Recording database (default $XDG_DATA_HOME/nlsoft/runs.db)");
  app.add_flag("--no-record", a.no_record, "Keep runs in a temporary database, deleted on exit");
  app.add_option("--db-busy", a.db_busy_s,
                 "Seconds a run's samples wait in memory while another process holds the database locked (a sqlite3 "
                 "shell in a transaction; default 30); past that they are counted lost until the lock goes, and the "
                 "run records the gap and for how long the database was locked")
      ->check(CLI::PositiveNumber);
  app.add_option("--sim-rate", a.sim_rate, "Control loop rate of the simulator, Hz")->check(CLI::PositiveNumber);
  app.add_flag("--sim-fast", a.sim_fast, "Let the simulator run faster than real time");
  app.add_option("--sim-settings", a.sim_settings,
                 "The simulator's settings flash, where `settings save` (W in the TUI) keeps the parameters across "
                 "a restart (default: one file per rig beside the recording database, <db>.RIG.settings; "
                 "none under --no-record; none: a simulator that keeps "
                 "no settings)");
  app.add_option("--timeout", a.timeout_ms, "Reply timeout per try, ms (3 retries follow)")->check(CLI::Range(10, 60000));
}

LiveOptions live_options(const ConnectArgs& a, const std::string& command) {
  const std::string who = command.empty() ? "" : command + ": ";
  const std::string cmd = command.empty() ? "" : command + " ";
  const TargetArgs& t = a.target;
  if (!a.rig.empty() && t.port.empty())
    throw CliError(who + "--rig names the rig of a board given by PORT; with --sim or --qemu the rig is theirs");
  // The rig loaded here once (--qemu's image found or built) for everything below.
  Target target = resolve_target(t, who);
  if (target.port.empty() && !target.rig) target.port = pick_port(who, cmd);
  LiveOptions o;
  o.port = target.port;
  o.baud = a.baud;
  o.qemu_image = target.qemu_image;
  o.sim_rig = target.sim_rig;
  o.rig = target.rig;
  if (!a.rig.empty()) o.rig = load_rig_option(a.rig, who + "--rig");  // a bad file is said before the board is touched
  o.sim_in_qemu = !t.qemu.empty();
  o.qemu_board = t.board;
  if (a.sim_rate > 0) o.sim_args.insert(o.sim_args.end(), {"--rate", fmt::format("{:g}", a.sim_rate)});
  if (a.sim_fast) o.sim_args.push_back("--fast");
  if (!a.sim_settings.empty() && t.sim.empty()) throw CliError(who + "--sim-settings is for --sim's simulator; give --sim too");
  if (!t.sim.empty())
    if (const std::string file = sim_settings_file(a, *o.rig, who); !file.empty())
      o.sim_args.insert(o.sim_args.end(), {"--settings", file});
  o.db_path = a.db;
  o.record = !a.no_record;
  o.db_busy = std::chrono::milliseconds(int64_t(a.db_busy_s * 1000));
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
