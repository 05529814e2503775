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
  // sum / count without a 64-bit division (a libgcc call of 700 B on a
  // Cortex-M): the mean is at most max, so the quotient fits 32 bits and a
  // 32-step shift-and-subtract finds it.
  uint32_t mean() const {
    if (count == 0) return 0;
    uint64_t rem = sum >> 32;  // < count, as sum / count < 2^32
    const uint32_t low = uint32_t(sum);
    uint32_t q = 0;
    for (int bit = 31; bit >= 0; --bit) {
      rem = rem << 1 | (low >> bit & 1u);
      q <<= 1;
      if (rem >= count) {
        rem -= count;
        q |= 1u;
      }
    }
    return q;
  }
  void reset() { *this = ComputeStats{}; }
};

}  // namespace nlsoft::fw
