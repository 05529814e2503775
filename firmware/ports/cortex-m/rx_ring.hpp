#pragma once
// The receive ring every Cortex-M port fills from its UART interrupt and the
// main loop drains. One producer (the handler) writes only head, one
// consumer (the loop) writes only tail: on a single core two indices and
// compiler barriers suffice, with no lock and no masked interrupts. A byte
// that finds the ring full is dropped and counted (the protocol's CRC and
// retries recover the frame).
#include <cstddef>
#include <cstdint>

namespace nlsoft::fw::cortex_m {

template <uint32_t N>
class RxRing {
  static_assert(N != 0 && (N & (N - 1)) == 0, "a power of two: indices wrap by masking");

 public:
  // Interrupt context.
  void push(uint8_t b) {
    const uint32_t h = head_;
    if (h - tail_ < N) {
      buf_[h & (N - 1)] = b;
      __asm volatile("" ::: "memory");  // the byte is in before the index moves
      head_ = h + 1;
    } else {
      lost_ = lost_ + 1;
    }
  }

  // Loop context: up to cap bytes, oldest first.
  size_t read(uint8_t* out, size_t cap) {
    const uint32_t h = head_;
    uint32_t t = tail_;
    size_t n = 0;
    while (t != h && n < cap) out[n++] = buf_[t++ & (N - 1)];
    __asm volatile("" ::: "memory");  // bytes copied out before the slot is freed
    tail_ = t;
    return n;
  }

  bool empty() const { return head_ == tail_; }
  uint32_t lost() const { return lost_; }

 private:
  uint8_t buf_[N] = {};  // initialised, so a global ring is constant-initialised (in .bss, before any handler runs)
  volatile uint32_t head_ = 0, tail_ = 0, lost_ = 0;
};

}  // namespace nlsoft::fw::cortex_m
