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
#include <fmt/format.h>

#include "app/cli_error.hpp"

namespace nlsoft::console {

namespace {

bool executable(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

std::string exe_dir() {
  char buf[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return {};
  std::string p(buf, size_t(n));
  return p.substr(0, p.rfind('/'));
}

}  // namespace

std::string find_firmware_sim() {
  std::vector<std::string> tried;
  if (const char* env = std::getenv("NLSOFT_FIRMWARE_SIM"); env && *env) {
    if (executable(env)) return env;
    tried.push_back(fmt::format("$NLSOFT_FIRMWARE_SIM={}", env));
  }
  const std::string dir = exe_dir();
  for (const char* rel : {"/../firmware/nlsoft-firmware-sim", "/nlsoft-firmware-sim"}) {
    const std::string cand = dir + rel;
    if (executable(cand)) return cand;
    tried.push_back(cand);
  }
  if (const char* path = std::getenv("PATH")) {
    std::string all = path;
    size_t pos = 0;
    while (pos <= all.size()) {
      const size_t colon = all.find(':', pos);
      const std::string d = all.substr(pos, colon == std::string::npos ? std::string::npos : colon - pos);
      pos = colon == std::string::npos ? all.size() + 1 : colon + 1;
      if (!d.empty() && executable(d + "/nlsoft-firmware-sim")) return d + "/nlsoft-firmware-sim";
    }
    tried.push_back("PATH");
  }
  std::string list;
  for (const auto& t : tried) list += "\n  " + t;
  throw CliError("cannot find nlsoft-firmware-sim; tried:" + list +
                 "\nbuild it (cmake --build build --target nlsoft-firmware-sim) or set NLSOFT_FIRMWARE_SIM");
}

std::string SimLauncher::start(const std::string& platform, const std::vector<std::string>& extra_args) {
  stop();
  const std::string exe = find_firmware_sim();
  int out[2];
  if (::pipe2(out, O_CLOEXEC) != 0) throw CliError(fmt::format("pipe: {}", std::strerror(errno)));
  log_path_ = fmt::format("/tmp/nlsoft-firmware-sim.{}.log", ::getpid());
  std::vector<std::string> args = {exe, "--platform", platform};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
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
    const int log = ::open(log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (log >= 0) ::dup2(log, STDERR_FILENO);
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(out[1]);
  pid_ = pid;
  out_fd_ = out[0];
  // First line = the pty path; wait a few seconds for the child to print it.
  std::string line;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (line.find('\n') == std::string::npos) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd pfd{out_fd_, POLLIN, 0};
    if (::poll(&pfd, 1, int(left.count())) <= 0) break;
    char buf[256];
    const ssize_t n = ::read(out_fd_, buf, sizeof buf);
    if (n <= 0) break;
    line.append(buf, size_t(n));
  }
  const size_t nl = line.find('\n');
  if (nl == std::string::npos) {
    int status = 0;
    const bool exited = ::waitpid(pid_, &status, WNOHANG) == pid_;
    if (exited) pid_ = -1;
    stop();
    throw CliError(fmt::format("{} did not report its pty{}; see {}", exe,
                               exited ? fmt::format(" (exit status {})", WEXITSTATUS(status)) : "", log_path_));
  }
  std::string path = line.substr(0, nl);
  if (!path.empty() && path.back() == '\r') path.pop_back();
  // Keep draining stdout so the simulator never blocks on a full pipe.
  drain_ = std::thread([fd = out_fd_] {
    char buf[1024];
    while (::read(fd, buf, sizeof buf) > 0) {
    }
  });
  return path;
}

void SimLauncher::stop() {
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
