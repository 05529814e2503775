#pragma once
// Infineon DPS310 barometric pressure sensor (datasheet v01_02), I²C at
// 0x77 (SDO high; 0x76 low) up to 3.4 MHz, or SPI up to 10 MHz in mode 3:
// the pneumatic rigs' pressure sensor. PRODUCT_ID (0x0D)
// reads 0x10: revision 1, product 0.
#include "shared/chips/chip_spec.hpp"

namespace nlsoft::chips {

namespace dps310 {
inline constexpr const char* kChannels[] = {"pressure", "temperature"};
inline constexpr const char* kUnits[] = {"Pa", "degC"};
// PRS_CFG / TMP_CFG PM_RATE (bits 6:4): measurements per second.
inline constexpr Setting kRates[] = {{1.0f, 0x00},  {2.0f, 0x10},  {4.0f, 0x20},  {8.0f, 0x30},
                                     {16.0f, 0x40}, {32.0f, 0x50}, {64.0f, 0x60}, {128.0f, 0x70}};
}  // namespace dps310

inline constexpr ChipSpec kDps310 = {
    "dps310", true, true, 0x77, true, 0x0D, 0x10, dps310::kChannels, dps310::kUnits, 2,
    nullptr, nullptr, 0, dps310::kRates, 8, 10000000, 3};

}  // namespace nlsoft::chips
