#pragma once
// The tick: the DWT cycle counter, one count per core clock, so compute time
// is in core cycles. QEMU models no DWT (CYCCNT reads 0); there the tick
// falls back to SysTick extended by its interrupt (cortex-m/systick.cpp),
// which counts the same core clock once SysTick runs.
#include <cstdint>

namespace nlsoft::fw::stm32f4 {

// Starts CYCCNT and reports whether it counts.
bool cycle_counter_start();
// CYCCNT when it counts, else the SysTick-derived tick.
uint32_t cycle_counter_ticks();

}  // namespace nlsoft::fw::stm32f4
