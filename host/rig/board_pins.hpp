#pragma once
// The pins and buses a rig file may name, per board: what the firmware's own
// tables wire (shared/board_stm32f4.hpp; the mps2-an386 port's buses.hpp),
// one per board of the board table (board_table.hpp, its PinTable),
// read from those tables where the host can see them, so the file and the
// image cannot disagree about which pins and buses exist.
#include <cstdint>
#include <string>
#include <vector>

#include "shared/firmware_features.hpp"
#include "shared/rig_devices.hpp"

namespace nlsoft::host {

struct BoardBus {
  std::string name;               // as a rig file names it: "i2c1", "spi2", "i2c-shield1"
  BusKind kind;
  std::vector<std::string> pins;  // the pins it takes (SCL SDA; SCK MISO MOSI); none where its lines are its own
  bool own_chip_select = false;   // SPI: one chip, on the controller's own select line (no GPIO chip selects)
  uint32_t max_clock_hz = 0;      // the fastest clock the port runs the bus at
  // Serial: whether the port's USART makes `baud` (on every part the board may carry).
  bool (*makes_baud)(uint32_t baud) = nullptr;
};

struct BoardPins {
  std::string board;
  // A rig file's `board` may name it. The MPS2 boards (QEMU's) have no pins
  // to wire actuators or ADC sensors to, only their shield buses: a rig file
  // names one to put sensor chips where QEMU's chip models are.
  bool rig_board = false;
  std::vector<std::string> pwm;       // PWM outputs by pin name ("PC6"), in the table's order
  std::vector<int> adc;               // ADC1 channels brought out, in the table's order
  std::vector<std::string> adc_pins;  // the pin of each of those channels ("PA6"), same order
  std::vector<BoardBus> buses;
  std::vector<std::string> chip_selects;  // GPIO chip selects of SPI chips, in the order SpiTarget::cs counts them
  // The services of shared/firmware_features.hpp the board's port can carry
  // (the port's NLSOFT_BOARD_SETTINGS says the same for its build).
  uint32_t firmware_features = kAllFirmwareFeatures & ~feature::kSettings;
  std::string settings_flash;  // where the port keeps saved settings; empty: nowhere
};

// The board's port cannot carry `f`: why, for a rig file's error; empty when it can.
std::string board_lacks(const BoardPins& board, const FirmwareFeature& f);

// nullptr for a board without a pin table.
const BoardPins* find_board(const std::string& name);
// The boards a rig file's `board` may name.
std::vector<std::string> board_names();

}  // namespace nlsoft::host
