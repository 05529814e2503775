#include "app/conformance/command.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <string>

#include "host/files/cli_error.hpp"
#include "app/conformance/report.hpp"
#include "app/conformance/suite.hpp"
#include "app/link/sim_launcher.hpp"
#include "app/target/target_args.hpp"

namespace nlsoft::console {

using host::CliError;
using host::CliExit;
using host::kDefaultQemuBoard;

namespace {

using namespace conformance;

struct ConformanceArgs {
  TargetArgs target;  // PORT, --sim, --qemu, --board
  std::string model;
  unsigned baud = 115200;
  bool json = false, shape_list = false;
  int timeout_ms = 250;
};

int run_conformance(const ConformanceArgs& a) {
  const TargetArgs& t = a.target;
  if (int(!t.port.empty()) + int(!t.sim.empty()) + int(!t.qemu.empty()) != 1)
    throw CliError(
        "give one of: a serial port (nlsoft-console conformance /dev/ttyACM0), --sim RIG or --qemu RIG");
  if (a.shape_list && t.sim.empty())
    throw CliError("--shape-list makes the simulator list its shapes; give --sim too");
  if (!a.model.empty() && !t.port.empty())
    throw CliError("--model names the model --sim or --qemu starts with; a board runs the model it holds");
  const Target target = resolve_target(t, "", a.model);
  SimLauncher launcher;
  Summary summary;
  summary.port = target.port;
  summary.target = target.port;
  if (!target.sim_rig.empty()) {
    std::vector<std::string> args;
    if (!a.model.empty()) args = {"--model", a.model};
    if (a.shape_list) args.push_back("--shape-list");
    summary.port = launcher.start(target.sim_rig, args);
    summary.target = "sim " + target.rig->name;
  } else if (!target.qemu_image.empty()) {
    summary.port = launcher.start_qemu(target.qemu_image, target.board);
    summary.target = "qemu " + target.rig->name + (target.board == kDefaultQemuBoard ? "" : " on " + target.board);
  }
  // An emulated MCU answers a few times slower than the host simulator.
  const Ms timeout(t.qemu.empty() ? a.timeout_ms : std::max(a.timeout_ms, 500));
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
    suite.run(std::chrono::seconds(!t.port.empty() ? 10 : !t.qemu.empty() ? 20 : 3));
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
  add_target_options(*c, a->target, "Serial device of the board, e.g. /dev/ttyACM0", "test", ", any rig with a [plant]");
  c->add_option("--model", a->model,
                "With --sim or --qemu: the model the simulator starts with, or the image embeds (default: the rig's "
                "[model] file; with --qemu FILE, the model of the image `firmware build` made last from FILE). The "
                "run checks need a model in force")
      ->check(CLI::ExistingFile)
      ->type_name("FILE.nlsm");
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
