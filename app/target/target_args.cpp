#include "app/target/target_args.hpp"

#include <fmt/format.h>

#include "app/firmware/image_build.hpp"
#include "host/files/cli_error.hpp"
#include "host/rig/board_option.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_plant.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::board_validator;
using host::describe_boards;
using host::kDefaultQemuBoard;
using host::load_rig_arg;
using host::qemu_board_names;
using host::rig_arg_help;
using host::simulated_plant;

std::shared_ptr<const Rig> load_rig_option(const std::string& arg, const std::string& option) {
  try {
    return std::make_shared<const Rig>(load_rig_arg(arg));
  } catch (const CliError& e) {
    throw CliError(option + ": " + e.what(), e.exit_code);
  }
}

void add_target_options(CLI::App& app, TargetArgs& a, const std::string& port_help, const std::string& what,
                        const std::string& sim_more) {
  app.add_option("PORT", a.port, port_help);
  // No validator on --sim and --qemu: resolve_target loads the rig, once.
  app.add_option("--sim", a.sim,
                 fmt::format("Start nlsoft-firmware-sim for this rig, {}{}, and {} it", rig_arg_help(), sim_more, what))
      ->type_name("RIG");
  app.add_option("--qemu", a.qemu,
                 fmt::format("Boot this rig's Cortex-M image (plant in the loop) in qemu-system-arm and {} it",
                             what))
      ->type_name("RIG");
  app.add_option("--board", a.board,
                 fmt::format("With --qemu: the board whose image QEMU boots: {} (default {})",
                             describe_boards(qemu_board_names()), kDefaultQemuBoard))
      ->check(board_validator(qemu_board_names(), "run under QEMU"));
}

Target resolve_target(const TargetArgs& a, const std::string& who, const std::string& model) {
  if (!a.qemu.empty() && !a.sim.empty()) throw CliError(who + "give either --sim or --qemu, not both");
  if (!a.port.empty() && !(a.sim.empty() && a.qemu.empty()))
    throw CliError(who + "give either a PORT or --sim/--qemu, not both");
  if (a.qemu.empty() && a.board != kDefaultQemuBoard)
    throw CliError(who + "--board names the image --qemu boots; give --qemu too");
  Target t;
  t.port = a.port;
  t.board = a.board;
  if (!a.qemu.empty()) {
    // The rig's HIL image: a shipped one, or built from its file.
    t.rig = load_rig_option(a.qemu, who + "--qemu");
    t.qemu_image = hil_image_for(*t.rig, a.board, who + "--qemu", model);
  } else if (!a.sim.empty()) {
    // Any rig file with a plant to simulate, checked here so a bad one is
    // said before a simulator starts.
    t.rig = load_rig_option(a.sim, who + "--sim");
    simulated_plant(*t.rig, who + "--sim");
    t.sim_rig = t.rig->file;
  }
  return t;
}

}  // namespace nlsoft::console
