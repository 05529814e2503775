#pragma once
// What every driver's read() promises, checked the same way for each chip.
#include <gtest/gtest.h>

#include <array>
#include <limits>

#include "fake_bus.hpp"
#include "firmware/drivers/chip.hpp"

namespace nlsoft::fw::drivers::check {

using Reading = std::array<float, kMaxChipChannels>;

// A read that must succeed: its values (NaN where it wrote nothing).
inline Reading read_ok(Chip& chip) {
  Reading out;
  out.fill(std::numeric_limits<float>::quiet_NaN());
  EXPECT_EQ(chip.read(out.data()), ChipStatus::kOk);
  return out;
}

// A read that must answer `want` and leave every value as it was.
inline void expect_refused(Chip& chip, ChipStatus want) {
  Reading out;
  for (int i = 0; i < kMaxChipChannels; ++i) out[static_cast<size_t>(i)] = 1000.0f + static_cast<float>(i);
  EXPECT_EQ(chip.read(out.data()), want);
  for (int i = 0; i < kMaxChipChannels; ++i)
    EXPECT_EQ(out[static_cast<size_t>(i)], 1000.0f + static_cast<float>(i)) << "value " << i << " written";
}

// A chip that boots and then stops answering (`device` off the bus): a bus
// fault, not a reading.
inline void expect_fault_once_silent(Chip& chip, fake::Device& device) {
  ASSERT_EQ(chip.begin(), ChipStatus::kOk);
  device.present = false;
  expect_refused(chip, ChipStatus::kBusFault);
}

}  // namespace nlsoft::fw::drivers::check
