#pragma once
// ST LIS3MDL 3-axis magnetometer (datasheet DocID024204): the paper's HASEL
// rig reads six of them over SPI at ±16 gauss, 1 kHz. I²C at 0x1C (SDO/SA1
// low; 0x1E high), up to 400 kHz; SPI up to 10 MHz in mode 3 (CPOL = CPHA =
// 1, the datasheet's timing; the paper's mode 0 also samples on the rising
// edge and works on the boards it was built with).
#include "shared/chips/chip_spec.hpp"

namespace nlsoft::chips {

namespace lis3mdl {
inline constexpr const char* kChannels[] = {"x", "y", "z"};
inline constexpr const char* kUnits[] = {"uT", "uT", "uT"};
// CTRL_REG2 FS[1:0] (bits 6:5).
inline constexpr Setting kRanges[] = {{4.0f, 0x00}, {8.0f, 0x20}, {12.0f, 0x40}, {16.0f, 0x60}};
// CTRL_REG1: DO[2:0] (bits 4:2) up to 80 Hz (OM low-power); FAST_ODR (bit 1)
// from 155 Hz, where OM[1:0] (bits 6:5) sets the rate: ultra-high
// performance 155, high 300, medium 560, low-power 1000 Hz. The same OM is
// written to CTRL_REG4's OMZ (bits 3:2) so z runs in x and y's mode.
inline constexpr Setting kRates[] = {{0.625f, 0x00}, {1.25f, 0x04}, {2.5f, 0x08}, {5.0f, 0x0C},
                                     {10.0f, 0x10},  {20.0f, 0x14}, {40.0f, 0x18}, {80.0f, 0x1C},
                                     {155.0f, 0x62}, {300.0f, 0x42}, {560.0f, 0x22}, {1000.0f, 0x02}};
}  // namespace lis3mdl

inline constexpr ChipSpec kLis3mdl = {
    "lis3mdl", true, true, 0x1C, true, 0x0F, 0x3D, lis3mdl::kChannels, lis3mdl::kUnits, 3,
    "gauss", lis3mdl::kRanges, 4, lis3mdl::kRates, 12, 10000000, 3};

}  // namespace nlsoft::chips
