#pragma once
// The pins a rig file may name, per board: what the firmware's own pin tables
// wire (shared/board_stm32f4.hpp), read from those tables so the
// file and the image cannot disagree about which pins exist.
#include <cstdint>
#include <string>
#include <vector>

#include "shared/rig_devices.hpp"

namespace nlsoft::console {

// A sensor bus of the board: what a [[device]]'s `bus` names. Its index in
// BoardPins::buses is the bus number the image's device table carries.
struct BoardBus {
  std::string name;               // "i2c1", "spi1"
  BusKind kind;
  std::vector<std::string> pins;  // the pins the controller takes (SCL, SDA / SCK, MISO, MOSI)
  uint32_t max_clock_hz;          // the fastest clock the controller runs the bus at
};

struct BoardPins {
  std::string board;
  std::vector<std::string> pwm;  // PWM outputs by pin name ("PC6"), in the table's order
  std::vector<int> adc;          // ADC1 channels brought out, in the table's order
  std::vector<BoardBus> buses;   // in the order the image numbers them
  // GPIO pins a SPI chip select may drive, in the order the image numbers
  // them; a PWM pin among them is a chip select only where no input drives it.
  std::vector<std::string> cs;
};

// nullptr for a board without a pin table.
const BoardPins* find_board(const std::string& name);
std::vector<std::string> board_names();

}  // namespace nlsoft::console
