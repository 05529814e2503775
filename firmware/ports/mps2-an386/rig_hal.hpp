#pragma once
// The real-board build: the link and the clock as on the HIL image, the
// actuators and sensors as stubs (the AN386 has nothing to drive). The
// image's size is the footprint we report for controller + protocol; a port
// with real outputs puts its PWM and ADC here (ports/stm32f4/rig_hal.hpp).
#include "firmware/core/hal.hpp"
#include "firmware/ports/cortex-m/board.hpp"

namespace nlsoft::fw::cortex_m {

template <int M, int W>
class RigHal final : public Hal {
 public:
  static constexpr bool kMeasuresOutput = false;
  size_t serial_read(uint8_t* buf, size_t cap) override { return board::serial_read(buf, cap); }
  size_t serial_write(const uint8_t* data, size_t len) override { return board::serial_write(data, len); }
  uint32_t ticks() override { return board::ticks(); }
  uint32_t tick_rate_hz() const override { return board::core_clock_hz(); }
  void actuate(const float*, int) override {}
  void read_sensors(float* l, int w) override {
    for (int i = 0; i < w; ++i) l[i] = 0.0f;
  }
  bool read_output(float*, int) override { return false; }  // no observer of y on a plain board
  void start() {}
  void advance() {}
};

}  // namespace nlsoft::fw::cortex_m
