#pragma once
// The real-board build: the link and the clock as on the HIL image, the
// actuators and sensors as stubs. A board port replaces actuate() with its
// PWM / DAC / servo writes and read_sensors() with its ADC or I2C reads; the
// image's size is the footprint we report for controller + protocol.
#include "firmware/core/hal.hpp"
#include "firmware/ports/mps2-an386/cmsdk_uart.hpp"
#include "firmware/ports/mps2-an386/systick.hpp"

namespace nlsoft::fw::an386 {

class BoardHal final : public Hal {
 public:
  size_t serial_read(uint8_t* buf, size_t cap) override { return uart_read(buf, cap); }
  size_t serial_write(const uint8_t* data, size_t len) override { return uart_write(data, len); }
  uint32_t ticks() override { return systick_ticks(); }
  uint32_t tick_rate_hz() const override { return kCoreClockHz; }
  void actuate(const float*, int) override {}
  void read_sensors(float* l, int w) override {
    for (int i = 0; i < w; ++i) l[i] = 0.0f;
  }
  bool read_output(float*, int) override { return false; }  // no observer of y on a plain board
  void advance() {}
};

}  // namespace nlsoft::fw::an386
