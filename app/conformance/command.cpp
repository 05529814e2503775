#include "app/conformance/command.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <string>

#include "host/files/cli_error.hpp"
#include "app/conformance/report.hpp"
#include "app/conformance/suite.hpp"
#include "app/firmware/image_build.hpp"
#include "app/link/sim_launcher.hpp"
#include "host/rig/board_option.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_plant.hpp"

namespace nlsoft::console {

namespace {

using namespace conformance;

struct ConformanceArgs {
  std::string port, sim, qemu, model, board = kDefaultQemuBoard;
  unsigned baud = 115200;
  bool json = false, shape_list = false;
  int timeout_ms = 250;
};

int run_conformance(const ConformanceArgs& a) {
  if (int(!a.port.empty()) + int(!a.sim.empty()) + int(!a.qemu.empty()) != 1)
    throw CliError(
        "give one of: a serial port (nlsoft-console conformance /dev/ttyACM0), --sim RIG or --qemu RIG");
  if (a.qemu.empty() && a.board != kDefaultQemuBoard)
    throw CliError("--board names the image --qemu boots; give --qemu too");
  SimLauncher launcher;
  Summary summary;
  summary.port = a.port;
  summary.target = a.port;
  if (a.shape_list && a.sim.empty())
    throw CliError("--shape-list makes the simulator list its shapes; give --sim too");
  if (!a.model.empty() && !a.port.empty())
    throw CliError("--model names the model --sim or --qemu starts with; a board runs the model it holds");
  if (!a.sim.empty()) {
    // Any rig with a plant to simulate, shipped or a file of the user's.
    const Rig rig = load_rig_arg(a.sim);
    simulated_plant(rig, "--sim");
    std::vector<std::string> args;
    if (!a.model.empty()) args = {"--model", a.model};
    if (a.shape_list) args.push_back("--shape-list");
    summary.port = launcher.start(rig.file, args);
    summary.target = "sim " + rig.name;
  } else if (!a.qemu.empty()) {
    // The rig's HIL image: a shipped one, or built from the file.
    const Rig rig = load_rig_arg(a.qemu);
    const std::string image = hil_image_for(rig, a.board, "--qemu", a.model);
    summary.port = launcher.start_qemu(image, a.board);
    summary.target = "qemu " + rig.name + (a.board == kDefaultQemuBoard ? "" : " on " + a.board);
  }
  // An emulated MCU answers a few times slower than the host simulator.
  const Ms timeout(a.qemu.empty() ? a.timeout_ms : std::max(a.timeout_ms, 500));
  Probe probe{timeout};
  Suite suite(probe, [&](const CheckResult& r) {
    if (!a.json) std::printf("%s\n", result_line(r).c_str()), std::fflush(stdout);
  });
  // Stderr, so --json's stdout stays one object.
  suite.on_link_error([](const std::string& what) {
    std::fprintf(stderr, "link error: %s; sending RUN_STOP to see whether the device answers again\n", what.c_str());
    std::fflush(stderr);
  });
  try {
    probe.open(summary.port, a.baud);
    // A board may be resetting, QEMU booting: ask for longer before giving up.
    suite.run(std::chrono::seconds(!a.port.empty() ? 10 : !a.qemu.empty() ? 20 : 3));
  } catch (const LinkError& e) {
    summary.link_error = e.what();
  }
  summary.checks = suite.results();
  std::fputs((a.json ? json_report(summary) : text_summary(summary)).c_str(), stdout);
  std::fflush(stdout);
  if (!summary.link_error.empty()) return 2;
  return summary.failed() ? 1 : 0;
}

}  // namespace

void add_conformance_command(CLI::App& app) {
  auto a = std::make_shared<ConformanceArgs>();
  CLI::App* c = app.add_subcommand(
      "conformance", "Run the protocol conformance suite (PROTOCOL.md) against a board, the simulator or QEMU");
  c->add_option("PORT", a->port, "Serial device of the board, e.g. /dev/ttyACM0");
  c->add_option("--sim", a->sim,
                "Start nlsoft-firmware-sim for this rig, " + rig_arg_help() + ", any rig with a [plant], and test it")
      ->check(rig_arg_validator());
  c->add_option("--qemu", a->qemu,
                "Boot this rig's Cortex-M4F image (simulated plant in the loop) in qemu-system-arm and test it")
      ->check(rig_arg_validator());
  c->add_option("--model", a->model,
                "With --sim or --qemu: the model the simulator starts with, or the image embeds (default: the rig's "
                "[model] file; with --qemu FILE, the model of the image `firmware build` made last from FILE). The "
                "run checks need a model in force")
      ->check(CLI::ExistingFile)
      ->type_name("FILE.nlsm");
  c->add_option("--board", a->board,
                fmt::format("With --qemu: the board whose image QEMU boots: {} (default {})",
                            describe_boards(qemu_board_names()), kDefaultQemuBoard))
      ->check(board_validator(qemu_board_names(), "run under QEMU"));
  c->add_flag("--shape-list", a->shape_list,
              "With --sim: the simulator lists the shapes it accepts (RIG_INFO accept 0), as an MCU image does, so "
              "the refusal of a model at XFER_BEGIN by its size is checked too");
  c->add_option("--baud", a->baud, "Baud rate (default 115200)")->check(CLI::Range(50u, 20000000u));
  c->add_option("--timeout", a->timeout_ms, "Reply timeout of the first try, ms (3 retries follow, each waiting twice as long as the one before)")->check(CLI::Range(10, 60000));
  c->add_flag("--json", a->json, "One JSON object instead of PASS/FAIL lines");
  c->footer(
      "Checks, by group: handshake (INFO/INFO_EX and its limits), basics (STATUS_GET, PING, frames\n"
      "that are no request), params (the list and its hash, every PARAM_SET refusal with its field\n"
      "and element, a valid set), references (every REF_SELECT refusal, unused fields ignored),\n"
      "framing (garbage, bursts, bad CRC, unknown types, bad lengths, every bit flip of a request,\n"
      "frames a byte at a time and back to back, duplicate, reused and replayed seq), run (start,\n"
      "stop, hold, neutral, resume and their refusals), telemetry (every frame received or counted\n"
      "in tx_dropped), watchdog (fed, tripped by silence, reported, resumed), transfers (a lost\n"
      "chunk healed, interrupted at each stage and resumed, every refusal), rig (RIG_INFO, models\n"
      "of refused shapes refused before their commit), ident (identification runs: refusals,\n"
      "samples, retry, hold, end, watchdog), and a summary: every message answered or seen,\n"
      "every reply with a seq of ours.\n"
      "Parameters it changes are set back. It leaves the hold reference selected, a small\n"
      "reference table committed (kind 1) and telemetry at decimation 1; it never uploads a model.\n"
      "Prints `PASS|FAIL name: detail` per check and `N passed, M failed`;\n"
      "exit 0 when all passed, 1 when one failed, 2 on a link error.\n"
      "Examples:\n"
      "  nlsoft-console conformance --sim hasel\n"
      "  nlsoft-console conformance --sim lab-arm.toml --model lab-arm.nlsm\n"
      "  nlsoft-console conformance --sim msd --shape-list\n"
      "  nlsoft-console conformance --qemu msd --json\n"
      "  nlsoft-console conformance --qemu hasel --board stm32f4\n"
      "  nlsoft-console conformance /dev/ttyACM0 --baud 1000000\n");
  c->callback([a] { throw CliExit{run_conformance(*a)}; });
}

}  // namespace nlsoft::console
