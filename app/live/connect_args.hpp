#pragma once
// What every live command (the console itself, tune) takes to reach a
// firmware and how it connects: one of PORT, --sim or --qemu (with
// --board), the link's baud and timeout, the simulator's speed, where runs
// are recorded. One definition, so the commands accept the same words and
// refuse the same mistakes in the same terms.
#include <CLI/CLI.hpp>
#include <string>

#include "app/live/live_console.hpp"
#include "app/target/target_args.hpp"

namespace nlsoft::console {

struct ConnectArgs {
  TargetArgs target;  // PORT, --sim, --qemu, --board
  std::string db, rig, sim_settings;
  unsigned baud = 115200;
  bool no_record = false, sim_fast = false;
  double sim_rate = 0;
  int timeout_ms = 250;
  double db_busy_s = 30;
};

// PORT, --sim, --qemu, --board, --rig, --baud, --sim-fast, --sim-rate, --db,
// --no-record, --timeout, --db-busy, --sim-settings. `what` is the verb of the help lines ("connect
// to", "tune").
void add_connect_options(CLI::App& app, ConnectArgs& a, const std::string& what);

// The options checked (exactly one of PORT, --sim, --qemu; --board only
// with --qemu) and turned into LiveOptions. Throws CliError whose words
// start with `command` ("tune: ...") when it is not empty.
LiveOptions live_options(const ConnectArgs& a, const std::string& command = "");

// Ctrl-C, SIGTERM, SIGHUP and SIGPIPE end the run in progress cleanly (it
// stays in the database, its end naming the signal) through
// request_interrupt.
void install_interrupt_handlers();

// connect() with a progress bar over the parameter list; link, refusal and
// database errors become CliError (exit 2 in words).
void connect_with_progress(LiveConsole& console);

}  // namespace nlsoft::console
