#pragma once
// `--sim PLATFORM`: starts nlsoft-firmware-sim, which serves the protocol on
// a pseudo-terminal and prints the pty's path as its first stdout line, and
// owns the child: it is terminated when this object goes away (and, via
// PR_SET_PDEATHSIG, if the console itself dies).
#include <sys/types.h>

#include <string>
#include <thread>
#include <vector>

namespace nlsoft::console {

// Where the simulator binary is: $NLSOFT_FIRMWARE_SIM, then next to the
// console (<exe_dir>/../firmware/nlsoft-firmware-sim), then PATH. Throws
// CliError listing what was tried.
std::string find_firmware_sim();

class SimLauncher {
 public:
  SimLauncher() = default;
  ~SimLauncher() { stop(); }
  SimLauncher(const SimLauncher&) = delete;
  SimLauncher& operator=(const SimLauncher&) = delete;

  // Returns the pty path. extra_args go after --platform (e.g. --rate 10000).
  std::string start(const std::string& platform, const std::vector<std::string>& extra_args = {});
  void stop();
  pid_t pid() const { return pid_; }
  const std::string& log_path() const { return log_path_; }

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
  std::thread drain_;
  std::string log_path_;
};

}  // namespace nlsoft::console
