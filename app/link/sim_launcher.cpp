#include "app/link/sim_launcher.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <fmt/format.h>

#include "host/files/cli_error.hpp"
#include "host/paths/install_paths.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Lookup;
using host::board_named;
using host::board_refusal;
using host::find_firmware_sim_file;
using host::find_image_file;
using host::qemu_board_names;
using host::qemu_machine_args;

namespace {

bool executable(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

}  // namespace

std::string find_firmware_sim() {
  const Lookup l = find_firmware_sim_file();
  if (!l.found.empty()) return l.found;
  throw CliError("cannot find nlsoft-firmware-sim; tried:" + l.tried_lines() +
                 "\nbuild it (cmake --build build --target nlsoft-firmware-sim), install it, or set NLSOFT_FIRMWARE_SIM");
}

std::string find_built_image(const std::string& rel) {
  const Lookup l = find_image_file(rel);
  if (!l.found.empty()) return l.found;
  throw CliError(fmt::format("cannot find the firmware image {}; tried:{}\nbuild it (needs arm-none-eabi-g++)", rel,
                             l.tried_lines()));
}

namespace {

// nlsoft-firmware-sim prints the path alone on its first line.
std::string first_line_path(const std::string& line) { return line; }

// QEMU: "char device redirected to /dev/pts/N (label serial0)".
std::string qemu_pty(const std::string& line) {
  const size_t at = line.find("redirected to /dev/");
  if (at == std::string::npos) return "";
  const size_t from = at + 14;
  const size_t to = line.find_first_of(" \t", from);
  return line.substr(from, to == std::string::npos ? std::string::npos : to - from);
}

}  // namespace

std::string SimLauncher::start(const std::string& rig, const std::vector<std::string>& extra_args) {
  std::vector<std::string> args = {find_firmware_sim(), "--rig", rig};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  return spawn(args, args[0], &first_line_path);
}

std::string SimLauncher::start_qemu(const std::string& elf, const std::string& board) {
  if (const std::string why = board_refusal(board, qemu_board_names(), "run under QEMU"); !why.empty())
    throw CliError(fmt::format("--board {}: {}", board, why));
  if (!executable("/usr/bin/qemu-system-arm") && !executable("/usr/local/bin/qemu-system-arm"))
    throw CliError("qemu-system-arm is not installed (apt-get install qemu-system-arm)");
  std::vector<std::string> argv = {"qemu-system-arm", "-nographic", "-monitor", "none"};
  const std::vector<std::string> machine = qemu_machine_args(*board_named(board), elf);
  argv.insert(argv.end(), machine.begin(), machine.end());
  return spawn(argv, "qemu-system-arm", &qemu_pty);
}

std::string SimLauncher::spawn(const std::vector<std::string>& argv_in, const std::string& what,
                               std::string (*pick)(const std::string& line)) {
  stop();
  int out[2];
  if (::pipe2(out, O_CLOEXEC) != 0) throw CliError(fmt::format("pipe: {}", std::strerror(errno)));
  if (log_dir_.empty()) {
    std::string tmpl = "/tmp/nlsoft-sim.XXXXXX";
    if (!::mkdtemp(tmpl.data())) throw CliError(fmt::format("cannot create a folder in /tmp: {}", std::strerror(errno)));
    log_dir_ = tmpl;
  }
  log_path_ = log_dir_ + "/" + std::filesystem::path(what).filename().string() + ".log";
  std::vector<std::string> args = argv_in;
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw CliError(fmt::format("fork: {}", std::strerror(errno)));
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    // Its own process group: Ctrl-C at the terminal is for the console,
    // which then stops the run and ends the simulator itself.
    ::setpgid(0, 0);
    if (::getppid() != parent) ::_exit(127);
    ::dup2(out[1], STDOUT_FILENO);
    const int log = ::open(log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (log >= 0) ::dup2(log, STDERR_FILENO);
    const int null_in = ::open("/dev/null", O_RDONLY);
    if (null_in >= 0) ::dup2(null_in, STDIN_FILENO);
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(out[1]);
  {
    std::lock_guard<std::mutex> lock(mu_);
    pid_ = pid;
    exit_words_.clear();
  }
  out_fd_ = out[0];
  // Read lines until one names the pty; give the child a few seconds.
  std::string buffer, path;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (path.empty()) {
    const size_t nl = buffer.find('\n');
    if (nl != std::string::npos) {
      std::string line = buffer.substr(0, nl);
      buffer.erase(0, nl + 1);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      path = pick(line);
      continue;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd pfd{out_fd_, POLLIN, 0};
    if (::poll(&pfd, 1, int(left.count())) <= 0) break;
    char buf[256];
    const ssize_t n = ::read(out_fd_, buf, sizeof buf);
    if (n <= 0) break;
    buffer.append(buf, size_t(n));
  }
  if (path.empty()) {
    int status = 0;
    bool exited = false;
    {
      std::lock_guard<std::mutex> lock(mu_);
      exited = ::waitpid(pid_, &status, WNOHANG) == pid_;
      if (exited) pid_ = -1;
    }
    stop();
    // The log goes with this object: quote its end rather than point at it.
    std::ifstream log(log_path_);
    std::string line, tail;
    while (std::getline(log, line)) tail = tail.size() > 600 ? line : tail + "\n  " + line;
    throw CliError(fmt::format("{} did not report its pty{}{}", what,
                               exited ? fmt::format(" (exit status {})", WEXITSTATUS(status)) : "",
                               tail.empty() ? "" : "; it said:" + tail));
  }
  // Keep draining stdout so the child never blocks on a full pipe.
  drain_ = std::thread([fd = out_fd_] {
    char buf[1024];
    while (::read(fd, buf, sizeof buf) > 0) {
    }
  });
  return path;
}

SimLauncher::~SimLauncher() {
  stop();
  if (!log_dir_.empty()) {
    std::error_code ec;
    std::filesystem::remove_all(log_dir_, ec);
  }
}

std::string SimLauncher::exit_words() {
  std::lock_guard<std::mutex> lock(mu_);
  if (!exit_words_.empty() || pid_ <= 0) return exit_words_;
  int status = 0;
  if (::waitpid(pid_, &status, WNOHANG) != pid_) return "";
  pid_ = -1;
  if (WIFSIGNALED(status)) {
    const char* abbrev = ::sigabbrev_np(WTERMSIG(status));
    exit_words_ = abbrev ? fmt::format("killed by signal {} (SIG{})", WTERMSIG(status), abbrev)
                         : fmt::format("killed by signal {}", WTERMSIG(status));
  } else {
    exit_words_ = fmt::format("exited with status {}", WEXITSTATUS(status));
  }
  return exit_words_;
}

void SimLauncher::stop() {
  std::lock_guard<std::mutex> lock(mu_);
  if (pid_ > 0) {
    ::kill(pid_, SIGTERM);
    int status = 0;
    bool gone = false;
    for (int i = 0; i < 100 && !gone; ++i) {
      if (::waitpid(pid_, &status, WNOHANG) == pid_) gone = true;
      else ::usleep(10000);
    }
    if (!gone) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
    }
    pid_ = -1;
  }
  if (drain_.joinable()) drain_.join();
  if (out_fd_ >= 0) ::close(out_fd_), out_fd_ = -1;
}

}  // namespace nlsoft::console
