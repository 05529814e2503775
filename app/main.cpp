// nlsoft-console: tune a learned model-predictive controller on a
// microcontroller, or run it offline against simulated rigs.
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>

#include "host/files/cli_error.hpp"
#include "app/console_command.hpp"
#include "app/conformance/command.hpp"
#include "app/firmware/firmware_command.hpp"
#include "app/link/device_check.hpp"
#include "app/link/ports_command.hpp"
#include "app/live/flash_command.hpp"
#include "app/live/ident_command.hpp"
#include "app/model/commands.hpp"
#include "app/record/gnuplot.hpp"
#include "app/record/run_plot.hpp"
#include "app/record/run_training.hpp"
#include "app/record/runs_command.hpp"
#include "app/replay/replay_command.hpp"
#include "app/rig/rig_command.hpp"
#include "host/rig/rig_catalog.hpp"
#include "app/rig/rig_pipeline.hpp"
#include "app/simulate/simulate_command.hpp"
#include "app/tune/tune_command.hpp"
#include "app/link/protocol_version.hpp"

int main(int argc, char** argv) {
  using namespace nlsoft::console;
  using nlsoft::host::CliError;
  using nlsoft::host::CliExit;
  using nlsoft::host::rig_name_of_platform;
  // A file-size limit (ulimit -f) must make a write fail with EFBIG, which
  // the recorder and every file writer report, not kill the console
  // silently in the middle of a run (SIGXFSZ's default).
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{
      "nlsoft-console: tune a learned model-predictive controller running on a microcontroller,\n"
      "or run it offline against a simulated rig."};
  app.set_version_flag("--version", std::string("nlsoft-console " NLSOFT_VERSION ", wire protocol ") +
                                        protocol_version_text() + " (protocol/PROTOCOL.md)");
  // Every command, in one place. Without a subcommand the live console runs
  // (its options sit on the main app); at most one subcommand per call.
  app.require_subcommand(0, 1);
  add_runs_command(app);
  add_replay_command(*app.get_subcommand("runs"));
  add_ports_command(app);
  add_tune_command(app);
  add_conformance_command(app);
  add_flash_command(app);
  add_ident_command(app);
  add_firmware_command(app);
  add_simulate_command(app, [](const SimulationPicture& p) { return run_gnuplot(simulation_plot_script(p)); });
  // dataset and train take any rig file (or a shipped rig's name); train
  // reads recorded runs from the console's database.
  add_dataset_command(app, rig_target_arg);
  add_train_command(app, rig_target_arg, load_recorded_run);
  add_model_command(app, rig_target_arg, rig_name_of_platform, load_recorded_run, run_gnuplot);
  add_rig_command(app, check_live_devices);
  // Last: CLI11 copies the main app's footer into every subcommand made
  // after it is set, and the live console's footer (its examples and script
  // commands) is about the live console, not about `model` or `simulate`.
  add_live_console(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help); a usage error is exit 2, as
    // for every other bad input, not CLI11's own codes.
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const CliExit& e) {
    return e.code;
  } catch (const CliError& e) {
    std::fprintf(stderr, "nlsoft-console: error: %s\n", e.what());
    return e.exit_code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nlsoft-console: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
