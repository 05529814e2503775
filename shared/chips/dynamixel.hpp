#pragma once
// ROBOTIS Dynamixel servos as devices: actuators that are also sensors. Each
// speaks one packet protocol on a single-wire half-duplex serial bus
// (firmware/drivers/dynamixel_packet.hpp) and has a control table whose
// addresses depend on that protocol alone for what nlsoft uses (below); a
// model is identified by the model number it answers with. Values from the
// ROBOTIS e-manual's control tables (RX-64, MX-28 protocol 1.0, AX-12A;
// XL430-W250, XM430-W350).
//
// A servo "device" is read between control steps like a sensor chip (its
// present position, load and temperature: channels a rig's sensors may use)
// and written once per step: one SYNC_WRITE of every servo's goal position.
// Its status packet's error byte is its health: a servo that reports an
// error is a device in state `fault` (PROTOCOL.md, DEVICE_STATUS).
#include "shared/chips/chip_spec.hpp"

namespace nlsoft::chips {

namespace dynamixel {

// The control-table items nlsoft reads and writes, per protocol.
struct ControlTable {
  uint16_t model_number;  // 2 bytes
  uint16_t torque_enable; // 1 byte
  uint16_t goal_position;
  uint8_t goal_bytes;
  // One READ from `present_from`, `present_bytes` long, holds the present
  // position, load and temperature at these offsets.
  uint16_t present_from;
  uint8_t present_bytes;
  uint8_t position_at, position_bytes, load_at, temperature_at;
};
// 1.0 (RX, MX, AX): Present Position 36, Speed 38, Load 40, Voltage 42, Temperature 43.
inline constexpr ControlTable kTable1 = {0, 24, 30, 2, 36, 8, 0, 2, 4, 7};
// 2.0 (X series): Present Load/Current 126, Velocity 128, Position 132, ..., Temperature 146.
inline constexpr ControlTable kTable2 = {0, 64, 116, 4, 126, 21, 6, 4, 0, 20};
constexpr const ControlTable& table(uint8_t protocol) { return protocol == 1 ? kTable1 : kTable2; }

inline constexpr const char* kChannels[] = {"position", "load", "temperature"};
// position in goal-position steps; load as the servo reports it (1.0: 0.1 %
// of its torque, signed by direction; 2.0: its Present Load or Current item,
// signed); temperature in degrees Celsius.
inline constexpr const char* kUnits[] = {"step", "raw", "degC"};
// How often the servo is read between steps (a READ and its status packet);
// the bits are only the settings' distinct labels (no register takes them).
inline constexpr Setting kReadRates[] = {{10.0f, 0}, {25.0f, 1}, {50.0f, 2}, {100.0f, 3}};

constexpr ChipSpec servo(const char* name, uint8_t protocol, uint16_t model, uint32_t baud, uint32_t goal_max,
                         uint32_t max_baud) {
  return ChipSpec{name,      false,   false,    1,   false,    0, 0, kChannels, kUnits, 3, nullptr, nullptr, 0,
                  kReadRates, 4,      max_baud, 0,   protocol, model, baud, goal_max};
}

}  // namespace dynamixel

// The factory baud of the 1.0 models is register value 34 (2 Mbit/s / 35)
// but for the AX-12A's value 1 (1 Mbit/s); the X series leave at 57,600.
inline constexpr ChipSpec kRx64 = dynamixel::servo("rx-64", 1, 64, 57142, 1023, 1000000);
inline constexpr ChipSpec kMx28 = dynamixel::servo("mx-28", 1, 29, 57142, 4095, 3000000);
inline constexpr ChipSpec kAx12a = dynamixel::servo("ax-12a", 1, 12, 1000000, 1023, 1000000);
inline constexpr ChipSpec kXl430W250 = dynamixel::servo("xl430-w250", 2, 1060, 57600, 4095, 4500000);
inline constexpr ChipSpec kXm430W350 = dynamixel::servo("xm430-w350", 2, 1020, 57600, 4095, 4500000);

}  // namespace nlsoft::chips
