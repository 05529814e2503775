// The Nucleo-64 as the shared loop sees it: the clock tree at the part's top
// speed, the DWT cycle counter as the tick (SysTick-derived where it does
// not count), USART2 to the ST-LINK's virtual COM port, the IWDG.
#include "firmware/ports/cortex-m/board.hpp"

#include "firmware/ports/stm32f4/clock_tree.hpp"
#include "firmware/ports/stm32f4/cycle_counter.hpp"
#include "firmware/ports/stm32f4/usart2.hpp"
#include "firmware/ports/stm32f4/watchdog.hpp"

namespace nlsoft::fw::stm32f4 {

namespace {
Clocks g_clocks{};
}

const Clocks& board_clocks() { return g_clocks; }

}  // namespace nlsoft::fw::stm32f4

namespace nlsoft::fw::board {

using stm32f4::g_clocks;

void start(uint32_t baud) {
  g_clocks = stm32f4::start_clock_tree();
  (void)stm32f4::cycle_counter_start();
  stm32f4::usart2_start(g_clocks.apb1_hz, baud);
  stm32f4::watchdog_start();
}

uint32_t core_clock_hz() { return g_clocks.core_hz; }
uint32_t ticks() { return stm32f4::cycle_counter_ticks(); }
void watchdog_kick() { stm32f4::watchdog_kick(); }

}  // namespace nlsoft::fw::board

