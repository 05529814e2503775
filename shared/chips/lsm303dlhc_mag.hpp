#pragma once
// The magnetometer half of ST's LSM303DLHC (datasheet DocID018771), I²C only,
// at 0x1E. It has no WHO_AM_I: its identification register A reads 'H'.
#include "shared/chips/chip_spec.hpp"

namespace nlsoft::chips {

namespace lsm303dlhc_mag {
inline constexpr const char* kChannels[] = {"x", "y", "z"};
inline constexpr const char* kUnits[] = {"uT", "uT", "uT"};
// CRB_REG_M GN[2:0] (bits 7:5).
inline constexpr Setting kRanges[] = {{1.3f, 0x20}, {1.9f, 0x40}, {2.5f, 0x60}, {4.0f, 0x80},
                                      {4.7f, 0xA0}, {5.6f, 0xC0}, {8.1f, 0xE0}};
// CRA_REG_M DO[2:0] (bits 4:2).
inline constexpr Setting kRates[] = {{0.75f, 0x00}, {1.5f, 0x04}, {3.0f, 0x08},  {7.5f, 0x0C},
                                     {15.0f, 0x10}, {30.0f, 0x14}, {75.0f, 0x18}, {220.0f, 0x1C}};
}  // namespace lsm303dlhc_mag

inline constexpr ChipSpec kLsm303dlhcMag = {
    "lsm303dlhc_mag", true, false, 0x1E, true, 0x0A, 0x48, lsm303dlhc_mag::kChannels, lsm303dlhc_mag::kUnits, 3,
    "gauss", lsm303dlhc_mag::kRanges, 7, lsm303dlhc_mag::kRates, 8, 400000, 0};

}  // namespace nlsoft::chips
