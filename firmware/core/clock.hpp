#pragma once
// Milliseconds and microseconds since boot from a wrapping 32-bit tick
// counter: fold each tick delta into whole seconds and the ticks of the
// second under way, so the clock survives the counter's wrap (171 s at
// 25 MHz) as long as it is read at least once per half wrap. Only 32-bit
// divisions: a 64-bit one is a libgcc call (__udivmoddi4, 700 B of flash on
// a Cortex-M and ≈ 130 instructions a reading, one of them in every step).
#include <cstdint>

namespace nlsoft::fw {

class Clock {
 public:
  void start(uint32_t ticks, uint32_t rate_hz) {
    last_ = ticks;
    rate_ = rate_hz ? rate_hz : 1;
    total_ = 0;
    seconds_ = 0;
    rem_ = 0;
  }
  // A reading behind the last one (by less than half the counter's range)
  // is a port's counter glitch, not 2^32 ticks of progress: the clock holds
  // until the counter passes the last reading. So the clock must be read at
  // least once per half wrap (86 s at 25 MHz).
  void update(uint32_t ticks) {
    uint32_t delta = ticks - last_;
    if (delta > 0x80000000u) return;
    total_ += delta;
    last_ = ticks;
    // rem_ < rate_ always.
    const uint32_t whole = delta / rate_;
    seconds_ += whole;
    delta -= whole * rate_;
    if (delta >= rate_ - rem_) {
      rem_ = delta - (rate_ - rem_);
      ++seconds_;
    } else {
      rem_ += delta;
    }
  }
  // floor(total * 10^digits / rate) modulo 2^32, as a 64-bit division would give it.
  uint32_t ms() const { return seconds_ * 1000u + fraction(3); }
  uint32_t us() const { return seconds_ * 1000000u + fraction(6); }
  uint64_t total_ticks() const { return total_; }

 private:
  // floor(rem_ * 10^digits / rate_), one decimal digit at a time: each step
  // divides 10 x (x < rate_) by rate_, in 32 bits while 10 x fits, else (a
  // clock above 429 MHz) by subtracting.
  uint32_t fraction(int digits) const {
    uint32_t x = rem_, q = 0;
    for (int d = 0; d < digits; ++d) {
      uint32_t digit;
      if (rate_ <= 0xFFFFFFFFu / 10u) {
        x *= 10u;
        digit = x / rate_;
        x -= digit * rate_;
      } else {
        uint64_t x10 = uint64_t(x) * 10u;
        for (digit = 0; x10 >= rate_; ++digit) x10 -= rate_;
        x = uint32_t(x10);
      }
      q = q * 10u + digit;
    }
    return q;
  }

  uint32_t last_ = 0, rate_ = 1;
  uint64_t total_ = 0;
  uint32_t seconds_ = 0, rem_ = 0;  // total_ = seconds_ * rate_ + rem_, rem_ < rate_
};

}  // namespace nlsoft::fw
