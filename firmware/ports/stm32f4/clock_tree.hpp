#pragma once
// The clock tree: HSI -> PLL -> the part's top core clock (part.hpp), every
// wait bounded. What start_clock_tree() returns is the clock the part really
// runs at, and everything timed (SysTick period, baud rate, PWM period)
// derives from it, so a part left on HSI still keeps time.
#include <cstdint>

namespace nlsoft::fw::stm32f4 {

struct Clocks {
  uint32_t core_hz;
  uint32_t apb1_hz;        // USART2, I2C1, SPI2
  uint32_t apb2_hz;        // SPI1
  uint32_t apb1_timer_hz;  // TIM3/TIM4: twice APB1 when APB1 is divided
  bool rcc_present;        // false under an emulator that models no RCC
};

Clocks start_clock_tree();
// What board::start() reached (board.cpp), for the drivers started after it.
const Clocks& board_clocks();

}  // namespace nlsoft::fw::stm32f4
