// The image's sensor chips: the rig file's [[device]] tables as the
// constexpr device table the port builds its buses and drivers from, and per
// sensor channel where its value comes from (shared/rig_devices.hpp).
#include <fmt/format.h>

#include "app/firmware/generated_text.hpp"
#include "app/firmware/image_header.hpp"
#include "host/rig/board_pins.hpp"
#include "shared/chips/catalog.hpp"

namespace nlsoft::console {

using host::BoardPins;
using host::Rig;
using host::RigDevice;
using host::RigInput;
using host::RigSensor;
using host::SensorSource;
using host::find_board;

namespace {

// A float literal that reads back as the same float.
std::string flt(double v) {
  std::string s = fmt::format("{}", float(v));
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s + "f";
}

int catalog_row(const chips::ChipSpec* chip) {
  for (size_t i = 0; i < std::size(chips::kCatalog); ++i)
    if (chips::kCatalog[i] == chip) return int(i);
  throw std::logic_error("a device's chip is not in the catalog");
}

std::string servo_row(const RigDevice& d) {
  return fmt::format("    {{{}, chips::kCatalog[{}], {}, BusKind::Serial, {}, 0, {}u, {{0.0f, 0x00}}, {{{}, 0x{:02x}}}, {}}},"
                     "  // {} id {} on {} at {} baud, read at {} Hz, {} on a fault\n",
                     cpp_string_literal(d.name), catalog_row(d.chip), d.bus_index, d.address, d.clock_hz,
                     flt(d.rate_hz), d.rate_bits, d.release_on_fault ? "true" : "false", d.chip->name, d.address,
                     d.bus, d.clock_hz, d.rate_hz, d.release_on_fault ? "released" : "held");
}

std::string device_row(const RigDevice& d) {
  if (d.kind == BusKind::Serial) return servo_row(d);
  const bool i2c = d.kind == BusKind::I2c;
  std::string where = i2c ? fmt::format("at 0x{:02x}", d.address) : "chip select " + d.cs;
  std::string settings = fmt::format("{} Hz clock", d.clock_hz);
  if (d.chip->range_count > 0) settings += fmt::format(", range {} {}", d.range, d.chip->range_unit);
  if (d.chip->rate_count > 0) settings += fmt::format(", {} Hz", d.rate_hz);
  return fmt::format("    {{{}, chips::kCatalog[{}], {}, BusKind::{}, 0x{:02x}, {}, {}u, {{{}, 0x{:02x}}}, {{{}, 0x{:02x}}}}},"
                     "  // {} on {} {}, {}\n",
                     cpp_string_literal(d.name), catalog_row(d.chip), d.bus_index, i2c ? "I2c" : "Spi",
                     i2c ? d.address : 0, i2c ? 0 : d.cs_index, d.clock_hz, flt(d.range), d.range_bits,
                     flt(d.rate_hz), d.rate_bits, d.chip->name, d.bus, where, settings);
}

std::string source_row(const Rig& rig, const RigSensor& s) {
  switch (s.source) {
    case SensorSource::Device: {
      const RigDevice& d = rig.devices[size_t(s.device)];
      return fmt::format("    {{SensorFrom::Device, {}, {}, {}, {}}},  // {}: {}'s {}\n", s.device, s.channel,
                         flt(s.gain), flt(s.offset), s.name, d.name, d.chip->channel_names[s.channel]);
    }
    case SensorSource::Adc:
      return fmt::format("    {{SensorFrom::Analogue, 0, 0, {}, {}}},  // {}: ADC1_IN{}\n", flt(s.gain),
                         flt(s.offset), s.name, s.adc);
    default: return fmt::format("    {{SensorFrom::None, 0, 0, 1.0f, 0.0f}},  // {}: not wired\n", s.name);
  }
}

// Which inputs servos drive, and how u becomes a goal position.
std::string servos_part(const Rig& rig) {
  int count = 0;
  std::string rows;
  for (const RigInput& in : rig.inputs) {
    if (in.servo_device < 0) {
      rows += fmt::format("    {{kNoServo, 0.0f, 0.0f, 0.0f}},  // {}: no servo\n", in.name);
      continue;
    }
    ++count;
    rows += fmt::format("    {{{}, {}, {}, {}}},  // {}: servo {}\n", in.servo_device, flt(in.neutral),
                        flt(in.goal_per_unit), flt(in.goal_at_neutral), in.name, in.servo);
  }
  std::string o = "// Input i's servo: {device, neutral, goal_per_unit, goal_at_neutral}; goal = goal_at_neutral +\n"
                  "// goal_per_unit * (u - neutral), written to every servo in one SYNC_WRITE per step.\n";
  o += fmt::format("constexpr int kRigServoCount = {};\n", count);
  o += fmt::format("constexpr RigServoInput kRigServoInputs[{}] = {{\n{}}};\n", rig.inputs.size(), rows);
  return o;
}

}  // namespace

std::string devices_part(const Rig& rig) {
  std::string buses;
  if (const BoardPins* b = find_board(rig.board))
    for (size_t i = 0; i < b->buses.size(); ++i) buses += fmt::format("{}{} {}", i ? ", " : "", b->buses[i].name, i);
  std::string o;
  o += "}  // namespace nlsoft::fw::cortex_m\n#include \"shared/chips/catalog.hpp\"\n"
       "#include \"shared/rig_devices.hpp\"\nnamespace nlsoft::fw::cortex_m {\n";
  o += fmt::format("// The rig's sensor chips ([[device]]): name, chip, bus (board {}: {}), I2C address, chip\n"
                   "// select (a row of the board's chip-select table), clock, {{range, its bits}}, {{rate, its bits}}.\n",
                   rig.board, buses);
  o += fmt::format("constexpr int kRigDeviceCount = {};\n", rig.devices.size());
  // inline: one object of external linkage, which the port's chip table takes as a template argument.
  o += fmt::format("inline constexpr RigDeviceConfig kRigDevices[{}] = {{\n", rig.devices.empty() ? 1 : rig.devices.size());
  if (rig.devices.empty()) o += "    {},  // none\n";
  for (const RigDevice& d : rig.devices) o += device_row(d);
  o += "};\nstatic_assert(kRigDeviceCount <= kRigMaxDevices, \"more devices than a rig file may name\");\n";
  for (size_t i = 0; i < rig.devices.size(); ++i)
    o += fmt::format("static_assert(chips::same_name(kRigDevices[{}].chip->name, {}), \"the catalog's row\");\n", i,
                     cpp_string_literal(rig.devices[i].chip->name));
  o += "// Sensor channel i's source: an analogue input (the board's rows above), a device's channel\n"
       "// (value = offset + gain * the chip's reading), or none; {from, device, channel, gain, offset}.\n";
  o += fmt::format("constexpr RigSensorSource kRigSensorSources[{}] = {{\n", rig.sensors.empty() ? 1 : rig.sensors.size());
  if (rig.sensors.empty()) o += "    {SensorFrom::None, 0, 0, 1.0f, 0.0f},  // no sensor channel\n";
  for (const RigSensor& s : rig.sensors) o += source_row(rig, s);
  o += "};\n";
  o += servos_part(rig);
  return o;
}

}  // namespace nlsoft::console
