#pragma once
// The simulator a console started (--sim, --qemu) ending under it: a user's
// kill -9, a crash. Separate because it is told apart from a link that is
// merely down, so the run in progress ends with the real reason instead of
// staying RUNNING, and the simulator can be started again without leaving
// the console.
#include <memory>
#include <mutex>
#include <string>

#include "app/link/sim_launcher.hpp"
#include "app/live/live_options.hpp"

namespace nlsoft::console {

class SimulatorChild {
 public:
  explicit SimulatorChild(const LiveOptions& options) : options_(options) {}

  // With --sim or --qemu: starts it and returns its pty; "" without.
  std::string start();
  bool present() const { return launcher_ != nullptr; }
  // Any thread: how it ended ("simulator killed by signal 9 (SIGKILL)",
  // "simulator exited with status 3"); "" while it runs, or with none.
  // Kept until forget_exit(): a new simulator already running must not
  // hide that the old one's run still needs ending.
  std::string exit_words();
  // Starts a new simulator in place of one that has ended; returns its
  // pty. Call it on a thread that lives as long as the console (the TUI's
  // UI thread): the child is ended with the thread that forked it
  // (PR_SET_PDEATHSIG). Throws CliError.
  std::string respawn();
  // Once the console is connected to the new one (LiveConsole::reconnect_simulator).
  void forget_exit();
  // A new one the console could not connect to: back to "ended".
  void stop() { launcher_->stop(); }
  int pid() const { return launcher_ ? int(launcher_->pid()) : 0; }
  // At disconnect, after the session has closed.
  void end();

 private:
  std::string launch();  // --qemu's image or --sim's rig, as the options say

  const LiveOptions& options_;
  std::unique_ptr<SimLauncher> launcher_;
  std::mutex mu_;
  std::string gone_;
};

}  // namespace nlsoft::console
