#pragma once
// Per-step compute time in timer ticks: min, mean and max since the last
// reset, reported by STATUS. The mean keeps a 64-bit sum so 10 kHz runs of
// hours do not overflow.
#include <cstdint>

namespace nlsoft::fw {

struct ComputeStats {
  uint32_t min = 0xFFFFFFFFu, max = 0;
  uint64_t sum = 0;
  uint32_t count = 0;

  void add(uint32_t ticks) {
    if (ticks < min) min = ticks;
    if (ticks > max) max = ticks;
    sum += ticks;
    ++count;
  }
  uint32_t mean() const { return count ? uint32_t(sum / count) : 0; }
  void reset() { *this = ComputeStats{}; }
};

}  // namespace nlsoft::fw
