#include "host/rig/board_pins.hpp"

#include "shared/board_stm32f4.hpp"

namespace nlsoft::console {

namespace {

std::string pin_name(const fw::stm32f4::Pin& p) {
  return std::string("P") + char('A' + (p.port - fw::stm32f4::kGpioA) / 0x400u) + std::to_string(p.number);
}

BoardPins stm32f4() {
  BoardPins b;
  b.board = "stm32f4";
  for (const auto& o : fw::stm32f4::kPwm) b.pwm.push_back(pin_name(o.pin));
  for (const auto& a : fw::stm32f4::kAnalogue) b.adc.push_back(a.adc_channel);
  return b;
}

const std::vector<BoardPins>& boards() {
  static const std::vector<BoardPins> all = {stm32f4()};
  return all;
}

}  // namespace

const BoardPins* find_board(const std::string& name) {
  for (const BoardPins& b : boards())
    if (b.board == name) return &b;
  return nullptr;
}

std::vector<std::string> board_names() {
  std::vector<std::string> names;
  for (const BoardPins& b : boards()) names.push_back(b.board);
  return names;
}

}  // namespace nlsoft::console
