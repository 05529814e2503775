#include "firmware/ports/stm32f4/cycle_counter.hpp"

#include "firmware/ports/cortex-m/systick.hpp"
#include "firmware/ports/stm32f4/regs.hpp"

namespace nlsoft::fw::stm32f4 {

namespace {
constexpr uint32_t kDemcr = 0xE000EDFCu, kTrcEna = 1u << 24;
constexpr uint32_t kDwtCtrl = 0xE0001000u, kDwtCyccnt = 0xE0001004u, kCycCntEna = 1u << 0;
bool g_counts = false;
}  // namespace

bool cycle_counter_start() {
  reg(kDemcr) = reg(kDemcr) | kTrcEna;
  reg(kDwtCyccnt) = 0;
  reg(kDwtCtrl) = reg(kDwtCtrl) | kCycCntEna;
  const uint32_t first = reg(kDwtCyccnt);
  for (volatile int i = 0; i < 16; i = i + 1) {
  }
  g_counts = reg(kDwtCyccnt) != first;
  return g_counts;
}

uint32_t cycle_counter_ticks() { return g_counts ? reg(kDwtCyccnt) : cortex_m::systick_ticks(); }

}  // namespace nlsoft::fw::stm32f4
