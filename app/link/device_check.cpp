#include "app/link/device_check.hpp"

#include <fmt/format.h>

#include "app/link/device.hpp"
#include "app/link/session.hpp"
#include "host/files/printable.hpp"
#include "host/rig/board_pins.hpp"

namespace nlsoft::console {

using host::BoardBus;
using host::BoardPins;
using host::Rig;
using host::RigDevice;
using host::find_board;

namespace p = nlsoft::protocol;

namespace {

// Where a chip is, as the file spells it: "i2c1 at 0x1e", "spi1 chip select PA8".
std::string place(const Rig& rig, const p::DeviceStatus& d) {
  const BoardPins* board = find_board(rig.board);
  if (!board || d.bus >= board->buses.size()) return fmt::format("bus {} address {}", d.bus, d.address);
  const BoardBus& bus = board->buses[d.bus];
  if (bus.kind == BusKind::I2c) return fmt::format("{} at 0x{:02x}", bus.name, d.address);
  if (bus.kind == BusKind::Serial) return fmt::format("{} id {}", bus.name, d.address);
  if (bus.own_chip_select) return bus.name;
  return fmt::format("{} chip select {}", bus.name,
                     d.address < board->chip_selects.size() ? board->chip_selects[d.address] : "?");
}

std::string sample_words(const p::DeviceStatus& d) {
  const std::string age = d.age_ms == p::kNoSample ? "no sample yet" : fmt::format("latest sample {} ms old", d.age_ms);
  return fmt::format("{}, {} fault{}", age, d.faults, d.faults == 1 ? "" : "s");
}

}  // namespace

std::vector<std::string> device_lines(const Rig& rig, const std::vector<p::DeviceStatus>& found, int& bad) {
  std::vector<std::string> lines;
  bad = 0;
  std::vector<bool> seen(rig.devices.size(), false);
  for (const p::DeviceStatus& d : found) {
    const std::string name = d.name;  // escaped where Device::devices() decoded it
    const RigDevice* mine = nullptr;
    for (size_t i = 0; i < rig.devices.size(); ++i)
      if (rig.devices[i].name == name) mine = &rig.devices[i], seen[i] = true;
    const bool ok = d.state == uint8_t(p::DeviceState::Ok);
    bad += ok ? 0 : 1;
    lines.push_back(fmt::format("device {:<10} {} on {}: {}, {}", name, mine ? mine->chip->name : "(not in this file)",
                                place(rig, d), p::device_state_name(d.state), sample_words(d)));
  }
  for (size_t i = 0; i < rig.devices.size(); ++i)
    if (!seen[i]) {
      ++bad;
      lines.push_back(fmt::format("device {:<10} {}: not in the firmware (an image built from another file?)",
                                  rig.devices[i].name, rig.devices[i].chip->name));
    }
  if (found.empty() && rig.devices.empty()) lines.push_back("no sensor chips, in the file or the firmware");
  return lines;
}

int check_live_devices(const Rig& rig, const std::string& port, unsigned baud) {
  Session session;
  session.open(port, baud);
  session.write_raw({p::kDelimiter});  // ends whatever partial frame the peer holds
  Device device(session);
  device.handshake();
  const std::optional<p::RigInfo> fw_rig = device.rig();
  const std::string hash =
      !fw_rig ? std::string("no RIG_INFO")
      : fw_rig->rig_hash == rig.hash
          ? fmt::format("0x{:08x}, built from this file", rig.hash)
          : fmt::format("0x{:08x}, built from another file than this one (0x{:08x})", fw_rig->rig_hash, rig.hash);
  fmt::print("live on {}: rig '{}' ({})\n", port, device.rig_label(), hash);
  int bad = 0;
  for (const std::string& line : device_lines(rig, device.devices(), bad)) fmt::print("  {}\n", line);
  session.close();
  return bad == 0 ? 0 : 1;
}

}  // namespace nlsoft::console
