#pragma once
// The AN386's serial buses a rig may use, as QEMU 7.2's mps2-an386 maps them
// (hw/arm/mps2.c; `info qtree` lists the same). Four SBCON I²C controllers:
// touch (0x40022000) and audio (0x40023000) are internal and QEMU marks
// them full, so the two shield buses below are the ones a user's
// `-device` can land on; with no bus= it lands on shield1, the last one
// created (every one is named "i2c", so bus= cannot pick shield0 either).
// Five PL022 SPI controllers: APB (0x40020000) and LCD (0x40021000) are
// the board's own; `-device max1111` with no bus= lands on the ADC one.
// Every controller is clocked at the board's 25 MHz.
#include <cstdint>

namespace nlsoft::fw::an386 {

struct BusController {
  const char* name;  // as a rig file names the bus
  uint32_t base;
};

constexpr BusController kI2cBuses[] = {{"i2c-shield0", 0x40029000u}, {"i2c-shield1", 0x4002A000u}};
constexpr BusController kSpiBuses[] = {
    {"spi-shield0", 0x40025000u}, {"spi-shield1", 0x40026000u}, {"spi-adc", 0x40027000u}};

constexpr uint32_t kBusClockHz = 25000000u;

}  // namespace nlsoft::fw::an386
