#pragma once
// Bounded waits, shared by the ports' drivers. A flag that hardware sets may
// never come (an emulator that models no such peripheral, a dead oscillator,
// a bus held low), so every wait gives up after a number of polls and says
// whether the flag came.
#include <cstdint>

namespace nlsoft::fw::cortex_m {

template <class Ready>
bool wait_for(Ready ready, uint32_t spins = 100000u) {
  for (uint32_t i = 0; i < spins; ++i)
    if (ready()) return true;
  return false;
}

// Polls for at least `us` microseconds at `core_hz`: a poll takes one core
// clock or more, so the bound is never shorter than asked (a few times
// longer at most: an I/O read costs a handful of clocks).
constexpr uint32_t spins_for_us(uint32_t core_hz, uint32_t us) { return (core_hz / 1000000u) * us; }

}  // namespace nlsoft::fw::cortex_m
