#pragma once
// The tick and the loop's metronome: SysTick on the 25 MHz core clock,
// reloading once per control period. Its interrupt counts periods (the loop
// runs one step per period and sleeps in between) and extends the 24-bit
// down-counter to a free-running 32-bit tick. Under qemu-system-arm
// -icount shift=0 one instruction takes 1 ns of virtual time: 40 per tick.
#include <cstdint>

namespace nlsoft::fw::an386 {

constexpr uint32_t kCoreClockHz = 25000000u;

// period_ticks: 2 .. 2^24 core clocks.
void systick_start(uint32_t period_ticks);
// Free-running, wraps at 2^32 (172 s).
uint32_t systick_ticks();
// Periods elapsed since systick_start(), wraps at 2^32.
uint32_t systick_periods();

}  // namespace nlsoft::fw::an386
