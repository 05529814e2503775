#pragma once
// The sensor chips of a rig as a firmware holds them: each [[device]] of the
// rig file (docs/rig-file.md) as a row of plain data, and per sensor channel
// where its value comes from. An image gets both as constexpr tables from the
// header generated for its rig (kRigDevices, kRigSensorSources in
// nlsoft_rig.hpp); the firmware's SensorSampler (firmware/core/) reads them.
#include <cstdint>

#include "shared/chips/chip_spec.hpp"

namespace nlsoft {

// The most chips one rig file wires (the paper's platform, as it was built: six
// LIS3MDL); an image holds its own rig's count only.
constexpr int kRigMaxDevices = 8;

// Serial: a single-wire half-duplex UART of servos (chips::on_serial).
enum class BusKind : uint8_t { I2c = 0, Spi = 1, Serial = 2 };

struct RigDeviceConfig {
  const char* name;              // the rig file's device name (DEVICE_STATUS carries it)
  const chips::ChipSpec* chip;   // its row of shared/chips/catalog.hpp
  uint8_t bus;                   // index into the board's bus table, in the rig file's board order
  BusKind kind;
  uint8_t address;               // I²C: the 7-bit address; Serial: the servo's id
  uint8_t cs;                    // SPI: index into the board's chip-select table
  uint32_t clock_hz;             // at most the chip's and the bus's maximum; Serial: the bus's baud
  // The file's range and rate as the chip's settings (shared/chips/): the
  // value and its register bits; {0, 0} where the chip has no such setting.
  chips::Setting range, rate;
  // Serial: what the firmware does with a servo in `fault` (its status
  // reports an error): hold it at its last goal, or release it (torque off).
  bool release_on_fault = false;
};

// Input i's servo, when one drives it: the device (a row of the device
// table, on a serial bus; kNoServo when none) and its goal position for u:
// goal_at_neutral + goal_per_unit * (u - neutral), in the servo's steps.
constexpr uint8_t kNoServo = 0xFF;
struct RigServoInput {
  uint8_t device;
  float neutral, goal_per_unit, goal_at_neutral;
};

// Where sensor channel i is read: an analogue input of the board (the
// port's own table, in sensor order), channel `channel` of device `device`
// (value = offset + gain * the chip's reading in its unit), or nowhere.
enum class SensorFrom : uint8_t { None = 0, Analogue = 1, Device = 2 };

struct RigSensorSource {
  SensorFrom from;
  uint8_t device, channel;
  float gain, offset;
};

}  // namespace nlsoft

namespace nlsoft::chips {

// A generated device table names its chip by its catalog row and checks the
// row's name with this at compile time.
constexpr bool same_name(const char* a, const char* b) {
  while (*a != '\0' && *a == *b) ++a, ++b;
  return *a == *b;
}

}  // namespace nlsoft::chips
