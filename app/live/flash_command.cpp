#include "app/live/flash_command.hpp"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "host/files/cli_error.hpp"
#include "app/firmware/image_build.hpp"
#include "app/link/sim_launcher.hpp"
#include "host/rig/board_option.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_option.hpp"

namespace nlsoft::console {

using host::CliError;
using host::CliExit;
using host::add_rig_option;
using host::board_for;
using host::board_validator;
using host::describe_boards;
using host::find_on_path;
using host::flash_board_names;
using host::load_rig_arg;
using host::rig_arg_help;
using host::rig_arg_validator;

namespace {

struct FlashArgs {
  std::string board = flash_board_names().front(), rig, image, port = "/dev/ttyACM0", script;
  bool hil = false, no_connect = false;
};


int run_child(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  std::vector<std::string> copy = args;
  for (auto& s : copy) argv.push_back(s.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw CliError(fmt::format("fork: {}", std::strerror(errno)));
  if (pid == 0) {
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

int run_flash(const FlashArgs& a) {
  if (a.rig.empty()) throw CliError("flash: --rig is required (the rig whose image is written)");
  // Before anything else: without the flasher nothing below can help.
  const std::string openocd = find_on_path("openocd");
  if (openocd.empty())
    throw CliError(
        "openocd is not installed or not on PATH: apt-get install openocd (or write the .bin yourself with st-flash "
        "from stlink-tools; see firmware/ports/stm32f4/README.md)");
  // The rig's image: a shipped one, or built from its file (firmware build).
  const std::string image = !a.image.empty() ? a.image : image_for(load_rig_arg(a.rig), a.board, a.hil, "--rig");
  if (::access(image.c_str(), R_OK) != 0) throw CliError(fmt::format("cannot read the image {}", image));
  const std::string& config = board_for(a.board, "--board").openocd_config;
  std::fprintf(stderr, "flashing %s with %s (%s)\n", image.c_str(), openocd.c_str(), config.c_str());
  const int rc = run_child({openocd, "-f", config, "-c", fmt::format("program {{{}}} verify reset exit", image)});
  if (rc != 0)
    throw CliError(fmt::format("openocd failed (exit status {}): is the Nucleo plugged in by its ST-LINK USB port, "
                               "and may you use it (the udev rules of the openocd package, group plugdev)?",
                               rc));
  if (a.no_connect) return 0;
  // The console proper, as `nlsoft-console PORT --wait 10`: the ST-LINK's
  // serial port may re-enumerate after the reset.
  char self[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) throw CliError("cannot find the console's own executable to connect");
  self[n] = '\0';
  std::vector<std::string> args = {self, a.port, "--wait", "10"};
  if (!a.script.empty()) args.insert(args.end(), {"--script", a.script});
  std::fprintf(stderr, "flashed; connecting to %s\n", a.port.c_str());
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  ::execv(self, argv.data());
  throw CliError(fmt::format("cannot start the console: {}", std::strerror(errno)));
}

}  // namespace

void add_flash_command(CLI::App& app) {
  auto a = std::make_shared<FlashArgs>();
  CLI::App* c = app.add_subcommand("flash", "Write the firmware to a board with openocd, then connect to it");
  c->add_option("--board", a->board,
                 "The board: " + describe_boards(flash_board_names()) + ", through its on-board ST-LINK")
      ->check(board_validator(flash_board_names(), "be flashed (no openocd configuration: QEMU runs its images)"));
  add_rig_option(c, a->rig,
                 "Whose image (required): the rig, " + rig_arg_help() +
                     "; a rig file's image is built from it (firmware build)")
      ->check(rig_arg_validator());
  c->add_flag("--hil", a->hil, "The image with the simulated plant on the MCU (a bare board, nothing wired)");
  c->add_option("--image", a->image, "Flash this ELF instead of the built one");
  c->add_option("--port", a->port, "The board's serial port to connect to afterwards (default /dev/ttyACM0)");
  c->add_option("--script", a->script, "Run this script headless once connected");
  c->add_flag("--no-connect", a->no_connect, "Flash only");
  c->footer(
      "Runs: openocd -f board/st_nucleo_f4.cfg -c \"program IMAGE verify reset exit\"\n"
      "then: nlsoft-console PORT --wait 10\n"
      "Images: build/firmware/stm32f4/nlsoft-stm32f4-<rig>[-hil].elf for a shipped rig (bash cmake/dev build),\n"
      "otherwise the one `firmware build --rig FILE --board stm32f4` made, built now if it is not there.\n"
      "Examples:\n"
      "  nlsoft-console flash --board stm32f4 --rig hasel --hil\n"
      "  nlsoft-console flash --board stm32f4 --rig tendon --port /dev/ttyACM1\n");
  c->callback([a] { throw CliExit{run_flash(*a)}; });
}

}  // namespace nlsoft::console
