#pragma once
// What a command talks to: a board on PORT, a simulator it starts (--sim
// RIG), or a rig's image with its simulated plant booted in QEMU (--qemu
// RIG, --board). One definition of the options and one resolution of them,
// so the console, tune and conformance take the same words, refuse the same
// mistakes, and load the rig once, here, for everything below.
#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "host/rig/board_table.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

struct TargetArgs {
  std::string port, sim, qemu, board = host::kDefaultQemuBoard;
};

struct Target {
  std::string port;                 // PORT; empty with --sim, --qemu, or none given
  std::shared_ptr<const host::Rig> rig;  // --sim's or --qemu's rig; nullptr with PORT
  std::string sim_rig;              // --sim: the rig file the simulator, a process of its own, loads
  std::string qemu_image;           // --qemu: the HIL image QEMU boots on `board`
  std::string board = host::kDefaultQemuBoard;
};

// PORT, --sim, --qemu and --board. `port_help`: PORT's help line; `what`:
// the verb of the others' ("connect to", "test"); `sim_more`: what --sim
// adds to its help.
void add_target_options(CLI::App& app, TargetArgs& a, const std::string& port_help, const std::string& what,
                        const std::string& sim_more = "");

// The rig `arg` names (a shipped name or a file), loaded; a bad one is said
// in the option's name ("tune: --rig: unknown rig ..."), as a validator
// would say it. Throws CliError.
std::shared_ptr<const host::Rig> load_rig_option(const std::string& arg, const std::string& option);

// One of PORT, --sim and --qemu at most, --board only with --qemu; the
// rig of --sim (which must have a plant) or --qemu loaded, and --qemu's
// image found or built (embedding `model` when given: hil_image_for).
// Throws CliError whose words start with `who` ("tune: ").
Target resolve_target(const TargetArgs& a, const std::string& who, const std::string& model = "");

}  // namespace nlsoft::console
