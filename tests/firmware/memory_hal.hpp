#pragma once
// A firmware HAL for the core's tests: serial bytes in memory, a tick
// counter that advances a millisecond on every read, no actuators, zero
// sensors and no measured output. A test that needs more (sensors that
// follow u, a slow line) overrides those calls.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "firmware/core/hal.hpp"

namespace nlsoft::test {

class MemoryHal : public fw::Hal {
 public:
  std::deque<uint8_t> in;
  std::vector<uint8_t> out;
  size_t serial_read(uint8_t* buf, size_t cap) override {
    size_t n = 0;
    while (n < cap && !in.empty()) buf[n++] = in.front(), in.pop_front();
    return n;
  }
  size_t serial_write(const uint8_t* data, size_t len) override {
    out.insert(out.end(), data, data + len);
    return len;
  }
  uint32_t ticks() override { return t_ += 1000; }
  uint32_t tick_rate_hz() const override { return 1000000; }
  void actuate(const float*, int) override {}
  void read_sensors(float* l, int w) override {
    for (int i = 0; i < w; ++i) l[i] = 0;
  }
  bool read_output(float*, int) override { return false; }

 private:
  uint32_t t_ = 0;
};

}  // namespace nlsoft::test
