// How the simulator ended is read once from its launcher and kept, so
// every part that asks (a run's wait, its stop, the TUI's poll) says the
// same words.
#include "app/live/simulator_child.hpp"

#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;

std::string SimulatorChild::start() {
  if (!options_.sim_in_qemu && options_.sim_rig.empty()) return "";
  launcher_ = std::make_unique<SimLauncher>();
  return launch();
}

std::string SimulatorChild::launch() {
  return options_.sim_in_qemu ? launcher_->start_qemu(options_.qemu_image, options_.qemu_board)
                              : launcher_->start(options_.sim_rig, options_.sim_args);
}

std::string SimulatorChild::exit_words() {
  std::lock_guard<std::mutex> lock(mu_);
  if (!launcher_) return "";
  if (gone_.empty()) {
    const std::string words = launcher_->exit_words();
    if (!words.empty()) gone_ = (options_.sim_in_qemu ? "qemu-system-arm " : "simulator ") + words;
  }
  return gone_;
}

std::string SimulatorChild::respawn() {
  if (!launcher_) throw CliError("no simulator to restart: this console is connected to a port");
  if (exit_words().empty()) throw CliError("the simulator is running; nothing to restart");
  if (launcher_->pid() > 0) throw CliError("a new simulator is already starting");
  return launch();
}

void SimulatorChild::forget_exit() {
  std::lock_guard<std::mutex> lock(mu_);
  gone_.clear();
}

void SimulatorChild::end() {
  std::lock_guard<std::mutex> lock(mu_);
  launcher_.reset();
}

}  // namespace nlsoft::console
