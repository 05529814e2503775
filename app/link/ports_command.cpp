#include "app/link/ports_command.hpp"

#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "host/files/cli_error.hpp"
#include "app/link/serial_ports.hpp"

namespace nlsoft::console {

using host::CliExit;

namespace {

nlohmann::json port_json(const SerialPort& p) {
  auto text_or_null = [](const std::string& s) { return s.empty() ? nlohmann::json() : nlohmann::json(s); };
  nlohmann::json j;
  j["path"] = p.path;
  j["device"] = p.device;
  j["usb_id"] = text_or_null(p.usb_id);
  j["manufacturer"] = text_or_null(p.manufacturer);
  j["product"] = text_or_null(p.product);
  j["serial"] = text_or_null(p.serial);
  j["board"] = text_or_null(p.board);
  j["busy"] = !p.holders.empty();
  j["holders"] = nlohmann::json::array();
  for (const PortHolder& h : p.holders) j["holders"].push_back({{"pid", h.pid}, {"command", h.command}});
  return j;
}

int run_ports(bool json) {
  const PortRoots roots = PortRoots::from_environment();
  const std::vector<SerialPort> ports = list_serial_ports(roots);
  if (json) {
    nlohmann::json j;
    j["ports"] = nlohmann::json::array();
    for (const SerialPort& p : ports) j["ports"].push_back(port_json(p));
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  if (ports.empty()) {
    fmt::print("no serial ports found (looked in {} and {}/class/tty)\n", roots.by_id, roots.sysfs);
    return 0;
  }
  for (const SerialPort& p : ports) fmt::print("{}\n    {}\n", p.path, describe_port(p));
  const auto c = candidate_ports(ports);
  if (c.size() == 1) fmt::print("nlsoft-console without a port connects to {}\n", c.front().path);
  return 0;
}

}  // namespace

void add_ports_command(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  CLI::App* c = app.add_subcommand("ports", "List the serial ports: which look like a board, which are busy and by whom");
  c->add_flag("--json", *json, "One JSON object: {\"ports\": [{path, device, usb_id, board, busy, holders}, ...]}");
  c->footer(
      "Each port by its /dev/serial/by-id name when udev gave it one (it follows the board across replugs), then\n"
      "USB ttys without one; the USB vendor:product from sysfs, \"ST-LINK\" (a Nucleo board's probe, 0483:374b,\n"
      "...) or \"Teensy\" (16c0:0483, ...), and the processes that have it open (/proc/*/fd; other users'\n"
      "processes are only seen by root).\n"
      "Without a PORT, --sim or --qemu the console connects to the one port that looks like a board (or the\n"
      "only port there is) and says so.\n"
      "Examples:\n"
      "  nlsoft-console ports\n"
      "  nlsoft-console ports --json\n");
  c->callback([json] { throw CliExit{run_ports(*json)}; });
}

}  // namespace nlsoft::console
