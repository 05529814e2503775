#pragma once
// The loop's metronome: SysTick on the core clock, reloading once per
// control period. Its interrupt counts periods (the loop runs one step per
// period and sleeps in between) and extends the 24-bit down-counter to a
// free-running 32-bit tick for boards without a cycle counter.
#include <cstdint>

namespace nlsoft::fw::cortex_m {

// period_ticks: 2 .. 2^24 core clocks.
void systick_start(uint32_t period_ticks);
// Free-running at the core clock, wraps at 2^32.
uint32_t systick_ticks();
// Periods elapsed since systick_start(), wraps at 2^32.
uint32_t systick_periods();

}  // namespace nlsoft::fw::cortex_m
