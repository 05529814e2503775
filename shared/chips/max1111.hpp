#pragma once
// Maxim MAX1111: a 4-channel 8-bit SPI ADC (strain and capacitive sensors
// behind an amplifier), SPI mode 0, inputs single-ended against COM over
// 0 .. VREF (2.048 V internal). No identity register: a missing chip shows
// as a bus that reads all ones (framing the driver refuses) or all zeros (0 V,
// which no driver can tell from a chip; firmware/drivers/max1111.hpp).
#include "shared/chips/chip_spec.hpp"

namespace nlsoft::chips {

namespace max1111 {
inline constexpr const char* kChannels[] = {"ch0", "ch1", "ch2", "ch3"};
inline constexpr const char* kUnits[] = {"V", "V", "V", "V"};
}  // namespace max1111

inline constexpr ChipSpec kMax1111 = {
    "max1111", false, true, 0, false, 0, 0, max1111::kChannels, max1111::kUnits, 4,
    nullptr, nullptr, 0, nullptr, 0, 2000000, 0};

}  // namespace nlsoft::chips
