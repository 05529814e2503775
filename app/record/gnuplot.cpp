#include "app/record/gnuplot.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/files/cli_error.hpp"

extern char** environ;

namespace nlsoft::console {

using host::CliError;

namespace {

// The script and gnuplot's messages live in a private folder, removed on
// every way out.
struct TempFolder {
  std::string path;
  TempFolder() {
    char tmpl[] = "/tmp/nlsoft-plot-XXXXXX";
    if (!::mkdtemp(tmpl)) throw CliError(fmt::format("cannot create a temporary folder: {}", std::strerror(errno)));
    path = tmpl;
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

}  // namespace

std::string run_gnuplot(const std::string& script) {
  const char* env = std::getenv("NLSOFT_GNUPLOT");
  const std::string program = env && *env ? env : "gnuplot";
  TempFolder dir;
  const std::string script_path = dir.path + "/plot.gp", err_path = dir.path + "/stderr.txt";
  {
    std::ofstream out(script_path);
    out << script;
    if (!out.flush()) throw CliError(fmt::format("cannot write {}: {}", script_path, std::strerror(errno)));
  }
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw CliError(fmt::format("pipe: {}", std::strerror(errno)));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  std::string arg0 = program, arg1 = script_path;
  char* argv[] = {arg0.data(), arg1.data(), nullptr};
  pid_t pid = 0;
  const int rc = ::posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    if (rc == ENOENT)
      throw CliError(fmt::format("{} not found: runs plot draws with gnuplot (apt-get install gnuplot-nox), or set "
                                 "NLSOFT_GNUPLOT to its path",
                                 program));
    throw CliError(fmt::format("cannot run {}: {}", program, std::strerror(rc)));
  }
  std::string image;
  char buf[65536];
  while (true) {
    const ssize_t got = ::read(fds[0], buf, sizeof buf);
    if (got > 0) image.append(buf, size_t(got));
    else if (got == 0 || errno != EINTR) break;
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  std::stringstream err;
  err << std::ifstream(err_path).rdbuf();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || image.empty()) {
    std::string said = err.str();
    while (!said.empty() && (said.back() == '\n' || said.back() == ' ')) said.pop_back();
    throw CliError(fmt::format("{} failed ({}){}", program,
                               WIFEXITED(status) ? fmt::format("exit {}", WEXITSTATUS(status)) : "killed by a signal",
                               said.empty() ? "" : ": " + said));
  }
  return image;
}

}  // namespace nlsoft::console
