#pragma once
// `--sim PLATFORM`: starts nlsoft-firmware-sim, which serves the protocol on
// a pseudo-terminal and prints the pty's path as its first stdout line, and
// owns the child: it is terminated when this object goes away (and, via
// PR_SET_PDEATHSIG, if the console itself dies).
#include <sys/types.h>

#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "host/paths/install_paths.hpp"
#include "host/rig/board_table.hpp"

namespace nlsoft::console {

// Where the simulator binary is (find_firmware_sim_file: the environment,
// the build tree, the install prefix, PATH). Throws CliError listing every
// place tried.
std::string find_firmware_sim();

// A firmware image, `rel` under the build tree's firmware/ or the install
// prefix's share/nlsoft/firmware/. Throws CliError naming every place tried.
std::string find_built_image(const std::string& rel);

class SimLauncher {
 public:
  SimLauncher() = default;
  ~SimLauncher();  // stops the child and removes its log
  SimLauncher(const SimLauncher&) = delete;
  SimLauncher& operator=(const SimLauncher&) = delete;

  // Starts the simulator for a rig (a shipped name or a rig file) and returns
  // the pty path. extra_args go after --rig (e.g. --rate 10000).
  std::string start(const std::string& rig, const std::vector<std::string>& extra_args = {});
  // Boots a HIL image for `board` in qemu-system-arm with the link's UART
  // on a pty: the board table's machine and -serial arguments (board_table.hpp).
  std::string start_qemu(const std::string& elf, const std::string& board = host::kDefaultQemuBoard);
  void stop();
  pid_t pid() const {
    std::lock_guard<std::mutex> lock(mu_);
    return pid_;
  }
  // How the child ended, once it has (it is reaped here): "killed by signal
  // 9 (SIGKILL)", "exited with status 3"; "" while it runs, or when it was
  // never started or stopped by stop(). Any thread; cheap enough to poll.
  std::string exit_words();
  // The child's stderr, in a folder of our own (mode 0700) that goes with
  // this object: nobody else can plant a link there or read it meanwhile.
  const std::string& log_path() const { return log_path_; }

 private:
  // Forks argv with stdout on a pipe; returns the first stdout line for which
  // pick() yields a non-empty path.
  std::string spawn(const std::vector<std::string>& argv, const std::string& what,
                    std::string (*pick)(const std::string& line));
  mutable std::mutex mu_;  // pid_ and exit_words_: exit_words() is polled from another thread
  pid_t pid_ = -1;
  std::string exit_words_;
  int out_fd_ = -1;
  std::thread drain_;
  std::string log_dir_, log_path_;
};

}  // namespace nlsoft::console
