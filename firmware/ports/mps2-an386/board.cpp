// The AN386 as the shared loop sees it: a fixed 25 MHz clock (no clock tree
// to set up), SysTick as the tick (the FPGA image has no DWT cycle counter
// QEMU models) and no watchdog. Under qemu-system-arm -icount shift=0 one
// instruction takes 1 ns of virtual time: 40 per tick.
#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/cortex-m/systick.hpp"
#include "firmware/ports/mps2-an386/cmsdk_uart.hpp"

namespace nlsoft::fw::board {

namespace {
constexpr uint32_t kCoreClockHz = 25000000u;
}

void start(uint32_t baud) { an386::uart_start(kCoreClockHz, baud); }
uint32_t core_clock_hz() { return kCoreClockHz; }
uint32_t ticks() { return cortex_m::systick_ticks(); }
void watchdog_kick() {}

}  // namespace nlsoft::fw::board
