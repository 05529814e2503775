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
  // The sensor buses on the Nucleo-64's headers, until the board's own
  // table names them: I2C1 on PB8/PB9 (Arduino D15/D14); SPI1 on PB3-PB5
  // (PA5, its usual SCK, is the LED) and SPI2 on PB13-PB15. Standard
  // I2C fast mode; SPI at APB2 / 4 (SPI1) and APB1 / 2 (SPI2) at 84 MHz.
  b.buses = {{"i2c1", BusKind::I2c, {"PB8", "PB9"}, 400000},
             {"spi1", BusKind::Spi, {"PB3", "PB4", "PB5"}, 21000000},
             {"spi2", BusKind::Spi, {"PB13", "PB14", "PB15"}, 21000000}};
  // Chip selects: the free GPIOs on the headers (not an ADC input, USART2,
  // the LED, the button or a bus), then the PWM pins, for a rig that drives
  // fewer actuators than the board has timers.
  b.cs = {"PA8", "PA9", "PA10", "PA15", "PB10", "PB12", "PC10", "PC11", "PC12"};
  for (const std::string& p : b.pwm) b.cs.push_back(p);
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
