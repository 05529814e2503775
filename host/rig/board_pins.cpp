#include "host/rig/board_pins.hpp"

#include "host/rig/board_table.hpp"
#include "shared/board_stm32f4.hpp"

namespace nlsoft::host {

namespace {

std::string pin_name(const fw::stm32f4::Pin& p) {
  return std::string("P") + char('A' + (p.port - fw::stm32f4::kGpioA) / 0x400u) + std::to_string(p.number);
}

BoardPins stm32f4(const std::string& board) {
  namespace f4 = fw::stm32f4;
  BoardPins b;
  b.board = board;
  b.rig_board = true;
  for (const auto& o : f4::kPwm) b.pwm.push_back(pin_name(o.pin));
  for (const auto& a : f4::kAnalogue) {
    b.adc.push_back(a.adc_channel);
    b.adc_pins.push_back(pin_name(a.pin));
  }
  for (const auto& i : f4::kI2c) b.buses.push_back({i.name, BusKind::I2c, {pin_name(i.scl), pin_name(i.sda)}});
  for (const auto& s : f4::kSpi)
    b.buses.push_back({s.name, BusKind::Spi, {pin_name(s.sck), pin_name(s.miso), pin_name(s.mosi)}});
  for (const auto& p : f4::kChipSelect) b.chip_selects.push_back(pin_name(p));
  // I2C1 in fast mode; SPI at the prescaler's fastest, APB2 / 2 (SPI1) and APB1 / 2 (SPI2) at 84 MHz.
  for (BoardBus& bus : b.buses) bus.max_clock_hz = bus.kind == BusKind::I2c ? 400000u : 21000000u;
  // The servo buses at the 16x divider's fastest on the slowest part's APB2 (84 MHz / 16).
  for (const auto& u : f4::kServoBus) {
    BoardBus bus{u.name, BusKind::Serial, {pin_name(u.tx)}, false, 84000000u / 16u};
    bus.makes_baud = [](uint32_t baud) {
      for (uint32_t clock : f4::kServoBusClocksHz)
        if (!f4::baud_reachable(clock, baud)) return false;
      return true;
    };
    b.buses.push_back(bus);
  }
  b.firmware_features = kAllFirmwareFeatures;
  b.settings_flash = "flash sectors 1 and 2";  // firmware/ports/stm32f4/flash.hpp
  return b;
}

// The buses firmware/ports/mps2-an386/buses.hpp drives (a port header the
// host build cannot include; tests/firmware/test_board_buses.cpp holds the
// two lists equal), on every MPS2 FPGA image that has them at the AN386's
// addresses (the an500's port builds the an386's sources). The FPGA gives
// each bus lines of its own, and each PL022 one chip on its own frame select.
BoardPins mps2_shields(const std::string& board) {
  BoardPins b;
  b.board = board;
  b.rig_board = true;
  // The SBCON's SCL in fast mode at most; a PL022 at half its 25 MHz clock.
  for (const char* name : {"i2c-shield0", "i2c-shield1"}) b.buses.push_back({name, BusKind::I2c, {}, false, 400000u});
  for (const char* name : {"spi-shield0", "spi-shield1", "spi-adc"})
    b.buses.push_back({name, BusKind::Spi, {}, true, 12500000u});
  return b;
}

const std::vector<BoardPins>& pin_tables() {
  static const std::vector<BoardPins> all = [] {
    std::vector<BoardPins> t;
    for (const Board& b : boards())
      t.push_back(b.pins == PinTable::Stm32f4 ? stm32f4(b.name) : mps2_shields(b.name));
    return t;
  }();
  return all;
}

}  // namespace

std::string board_lacks(const BoardPins& board, const FirmwareFeature& f) {
  if (board.firmware_features & f.bit) return "";
  if (f.bit == feature::kSettings)
    return "board " + board.board + " has nowhere to keep saved settings (no settings flash: its port keeps none)";
  return "board " + board.board + "'s port cannot carry " + f.what;
}

const BoardPins* find_board(const std::string& name) {
  for (const BoardPins& b : pin_tables())
    if (b.board == name) return &b;
  return nullptr;
}

std::vector<std::string> board_names() {
  std::vector<std::string> names;
  for (const BoardPins& b : pin_tables())
    if (b.rig_board) names.push_back(b.board);
  return names;
}

}  // namespace nlsoft::host
