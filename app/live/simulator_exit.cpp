// The simulator a console started (--sim, --qemu) ending under it: a user's
// kill -9, a crash. Told apart from a link that is merely down, so the run
// in progress ends with the real reason instead of staying RUNNING, and
// the simulator can be started again without leaving the console.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "host/files/cli_error.hpp"
#include "app/live/live_console.hpp"

namespace nlsoft::console {

namespace p = protocol;

std::string LiveConsole::simulator_exit() {
  if (!sim_) return "";
  std::lock_guard<std::mutex> lock(sim_mu_);
  if (sim_gone_.empty()) {
    const std::string words = sim_->exit_words();
    if (!words.empty()) sim_gone_ = (options_.sim_in_qemu ? "qemu-system-arm " : "simulator ") + words;
  }
  return sim_gone_;
}

std::optional<RunSummary> LiveConsole::end_run_simulator_gone() {
  const std::string words = simulator_exit();
  if (words.empty()) return std::nullopt;
  // A timed run (run_for) sees the same and ends itself, with its missing
  // steps as the gap.
  if (timed_run_.load()) return std::nullopt;
  std::lock_guard<std::mutex> stopping(stop_mu_);
  const int64_t id = run_id_.load();
  if (id == 0) return std::nullopt;
  using clock = std::chrono::steady_clock;
  const auto last = have_last_step_ ? clock::time_point(clock::duration(last_sample_ns_.load())) : run_started();
  const double silent_s = std::chrono::duration<double>(clock::now() - last).count();
  // The frames the run would have had from its last sample to now.
  const double rate = loop_rate_hz() > 0 ? loop_rate_hz() : 100.0;
  const uint64_t missed = uint64_t(std::llround(silent_s * rate / std::max<uint16_t>(decimation_.load(), 1)));
  const uint64_t k = run_k_.load();
  run_lost_ += missed;
  recorder_->add_gap(id, k == 0 ? 0 : k - 1, missed, words, silent_s);
  return stop_run_locked(id, words);
}

std::string LiveConsole::respawn_simulator() {
  if (!sim_) throw CliError("no simulator to restart: this console is connected to a port");
  if (simulator_exit().empty()) throw CliError("the simulator is running; nothing to restart");
  if (sim_->pid() > 0) throw CliError("a new simulator is already starting");
  return options_.sim_in_qemu ? sim_->start_qemu(options_.qemu_image, options_.qemu_board)
                              : sim_->start(options_.sim_rig, options_.sim_args);
}

void LiveConsole::reconnect_simulator(const std::string& port) {
  end_run_simulator_gone();
  const p::Info before = device_->info();
  boot_at_down_ns_ = boot_ns_.load();
  session_->close();
  try {
    session_->open(port, options_.baud);
    handshake_patiently();
    device_->load_params();
  } catch (...) {
    // Back to "ended", so R can try again with another one.
    sim_->stop();
    throw;
  }
  const p::Status st = device_->status();
  tick_rate_hz_ = st.tick_rate_hz;
  // A new simulator starts from its defaults: the session's edits it does
  // not have are named, as after a board's reset.
  check_for_reset(before, device_->info(), st);
  configure_telemetry();
  {
    std::lock_guard<std::mutex> lock(sim_mu_);
    sim_gone_.clear();
  }
  recorder_->add_link_event(0, "restarted", fmt::format("simulator restarted on {} (PID {})", port, sim_->pid()));
}

}  // namespace nlsoft::console
