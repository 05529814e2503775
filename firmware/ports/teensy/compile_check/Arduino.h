#pragma once
// A stand-in for the slice of Teensyduino's Arduino.h the sketch and
// teensy_hal.hpp use, with the same signatures, so the port compiles with
// Debian's arm-none-eabi-g++ where Teensyduino is not installed
// (compile_check.sh). It declares and never defines: nothing here links or
// runs, and a call the real core lacks still compiles here only if it is
// declared below, so keep it to what Teensyduino has.
#include <stddef.h>
#include <stdint.h>

class usb_serial_class {
 public:
  void begin(long baud);
  int available();
  int read();
  int availableForWrite();
  size_t write(const uint8_t* buffer, size_t size);
};
extern usb_serial_class Serial;

uint32_t micros();
void analogWrite(uint8_t pin, int value);
void analogWriteResolution(unsigned int bits);
int analogRead(uint8_t pin);
constexpr uint8_t A0 = 14;

// ARM debug registers as Teensyduino's core names them (kinetis.h, imxrt.h).
#define ARM_DEMCR (*(volatile uint32_t*)0xE000EDFC)
#define ARM_DEMCR_TRCENA (1 << 24)
#define ARM_DWT_CTRL (*(volatile uint32_t*)0xE0001000)
#define ARM_DWT_CTRL_CYCCNTENA (1 << 0)
#define ARM_DWT_CYCCNT (*(volatile uint32_t*)0xE0001004)
#if defined(__IMXRT1062__)
extern "C" volatile uint32_t F_CPU_ACTUAL;
#endif
