#pragma once
// Milliseconds and microseconds since boot from a wrapping 32-bit tick
// counter: fold each tick delta into 64-bit totals, so the clock survives the
// counter's wrap (171 s at 25 MHz) as long as it is read at least once per
// half wrap.
#include <cstdint>

namespace nlsoft::fw {

class Clock {
 public:
  void start(uint32_t ticks, uint32_t rate_hz) {
    last_ = ticks;
    rate_ = rate_hz ? rate_hz : 1;
    total_ = 0;
  }
  // A reading behind the last one (by less than half the counter's range)
  // is a port's counter glitch, not 2^32 ticks of progress: the clock holds
  // until the counter passes the last reading. So the clock must be read at
  // least once per half wrap (86 s at 25 MHz).
  void update(uint32_t ticks) {
    const uint32_t delta = ticks - last_;
    if (delta > 0x80000000u) return;
    total_ += delta;
    last_ = ticks;
  }
  uint32_t ms() const { return uint32_t(total_ * 1000u / rate_); }
  uint32_t us() const { return uint32_t(total_ * 1000000u / rate_); }
  uint64_t total_ticks() const { return total_; }

 private:
  uint32_t last_ = 0, rate_ = 1;
  uint64_t total_ = 0;
};

}  // namespace nlsoft::fw
