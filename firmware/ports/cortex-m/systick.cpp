// ticks = base + elapsed in the current period, base advanced by one period
// in the interrupt; unsigned arithmetic makes the sum wrap at 2^32 whatever
// the period.
#include "firmware/ports/cortex-m/systick.hpp"

namespace {

struct SysTickRegs {
  volatile uint32_t csr, rvr, cvr, calib;
};
SysTickRegs& systick() { return *reinterpret_cast<SysTickRegs*>(0xE000E010u); }
// SCB ICSR: bit 26 PENDSTSET, the SysTick interrupt is pending.
uint32_t scb_icsr() { return *reinterpret_cast<volatile uint32_t*>(0xE000ED04u); }
constexpr uint32_t kPendSysTick = 1u << 26;

uint32_t g_period = 1;
volatile uint32_t g_base = 0, g_periods = 0;

}  // namespace

extern "C" void SysTick_Handler() {
  g_base = g_base + g_period;
  g_periods = g_periods + 1;
}

namespace nlsoft::fw::cortex_m {

void systick_start(uint32_t period_ticks) {
  SysTickRegs& s = systick();
  g_period = period_ticks;
  s.rvr = period_ticks - 1u;
  s.cvr = 0;
  s.csr = 0x7u;  // enable, interrupt, core clock
}

uint32_t systick_ticks() {
  // The counter reads 0 from the moment its interrupt is raised and reloads
  // on the next tick, but the interrupt may be taken later than that (QEMU
  // delivers it asynchronously; thread code may run with it masked): while it
  // is pending, the period that just ended is not in base yet and counts
  // here. Without that, a reading taken in that window is a period behind
  // the one before, and the clock folding deltas takes it for 2^32 ticks.
  // Re-read if the handler ran, or the interrupt was raised, between loads.
  uint32_t base, cvr, pending;
  do {
    base = g_base;
    pending = scb_icsr() & kPendSysTick;
    cvr = systick().cvr;
  } while (base != g_base || pending != (scb_icsr() & kPendSysTick));
  return base + (pending ? g_period : 0u) + (cvr == 0 ? 0u : g_period - cvr);
}

uint32_t systick_periods() { return g_periods; }

}  // namespace nlsoft::fw::cortex_m
