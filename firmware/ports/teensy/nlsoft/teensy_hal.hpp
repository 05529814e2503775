#pragma once
// The HAL over Teensyduino: the USB serial port (Serial) as the link, the
// ARM cycle counter as the tick, and the board's actuator and sensor
// functions, which the sketch supplies (board_actuate, board_read_sensors).
#include <Arduino.h>

#include "firmware/core/hal.hpp"

void board_actuate(const float* u, int m);
void board_read_sensors(float* l, int w);

class TeensyHal final : public nlsoft::fw::Hal {
 public:
  // Enables the cycle counter (Teensy 4 starts it already; 3.x does not).
  void begin() {
    ARM_DEMCR |= ARM_DEMCR_TRCENA;
    ARM_DWT_CTRL |= ARM_DWT_CTRL_CYCCNTENA;
  }

  size_t serial_read(uint8_t* buf, size_t cap) override {
    size_t n = 0;
    for (int avail = Serial.available(); avail > 0 && n < cap; --avail) buf[n++] = uint8_t(Serial.read());
    return n;
  }
  // Never blocks: only what fits in the USB buffer now; the core keeps the rest.
  size_t serial_write(const uint8_t* data, size_t len) override {
    const int room = Serial.availableForWrite();
    if (room <= 0) return 0;
    return Serial.write(data, len < size_t(room) ? len : size_t(room));
  }
  // Core clocks: the finest clock the board has, so STATUS reports compute
  // time in cycles. Wraps in 7 s at 600 MHz; the core reads it far more often.
  uint32_t ticks() override { return ARM_DWT_CYCCNT; }
  uint32_t tick_rate_hz() const override {
#if defined(__IMXRT1062__)  // Teensy 4.x: the clock can be changed at run time
    return F_CPU_ACTUAL;
#else
    return F_CPU;
#endif
  }
  void actuate(const float* u, int m) override { board_actuate(u, m); }
  void read_sensors(float* l, int w) override { board_read_sensors(l, w); }
  bool read_output(float*, int) override { return false; }  // no observer of y on the board
};
