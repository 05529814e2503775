// ticks = base + elapsed in the current period, base advanced by one period
// in the interrupt; unsigned arithmetic makes the sum wrap at 2^32 whatever
// the period.
#include "firmware/ports/mps2-an386/systick.hpp"

namespace {

struct SysTickRegs {
  volatile uint32_t csr, rvr, cvr, calib;
};
SysTickRegs& systick() { return *reinterpret_cast<SysTickRegs*>(0xE000E010u); }

uint32_t g_period = 1;
volatile uint32_t g_base = 0, g_periods = 0;

}  // namespace

extern "C" void SysTick_Handler() {
  g_base = g_base + g_period;
  g_periods = g_periods + 1;
}

namespace nlsoft::fw::an386 {

void systick_start(uint32_t period_ticks) {
  SysTickRegs& s = systick();
  g_period = period_ticks;
  s.rvr = period_ticks - 1u;
  s.cvr = 0;
  s.csr = 0x7u;  // enable, interrupt, core clock
}

uint32_t systick_ticks() {
  // The counter shows 0 from the moment the reload interrupt is raised, so 0
  // counts as the start of the next period; the handler runs before the next
  // instruction in thread mode, so base has moved by then. Re-read if the
  // handler ran between the two loads.
  uint32_t base, cvr;
  do {
    base = g_base;
    cvr = systick().cvr;
  } while (base != g_base);
  return base + (cvr == 0 ? 0u : g_period - cvr);
}

uint32_t systick_periods() { return g_periods; }

}  // namespace nlsoft::fw::an386
