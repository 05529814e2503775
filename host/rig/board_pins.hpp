#pragma once
// The pins a rig file may name, per board: what the firmware's own pin tables
// wire (shared/board_stm32f4.hpp), read from those tables so the
// file and the image cannot disagree about which pins exist.
#include <string>
#include <vector>

namespace nlsoft::console {

struct BoardPins {
  std::string board;
  std::vector<std::string> pwm;  // PWM outputs by pin name ("PC6"), in the table's order
  std::vector<int> adc;          // ADC1 channels brought out, in the table's order
};

// nullptr for a board without a pin table.
const BoardPins* find_board(const std::string& name);
std::vector<std::string> board_names();

}  // namespace nlsoft::console
