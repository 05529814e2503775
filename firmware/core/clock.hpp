#pragma once
// Milliseconds and microseconds since boot from a wrapping 32-bit tick
// counter: fold each tick delta into 64-bit totals, so the clock survives the
// counter's wrap (171 s at 25 MHz) as long as it is read at least once per wrap.
#include <cstdint>

namespace nlsoft::fw {

class Clock {
 public:
  void start(uint32_t ticks, uint32_t rate_hz) {
    last_ = ticks;
    rate_ = rate_hz ? rate_hz : 1;
    total_ = 0;
  }
  void update(uint32_t ticks) {
    total_ += uint32_t(ticks - last_);
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
