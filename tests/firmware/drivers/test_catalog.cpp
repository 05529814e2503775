// Every chip a rig file may name is consistent data: what the rig loader
// checks a file against and what the drivers take their register bits from.
#include <gtest/gtest.h>

#include <cstring>
#include <iterator>
#include <set>
#include <string>

#include "firmware/drivers/chip.hpp"
#include "shared/chips/catalog.hpp"

namespace nlsoft::chips {
namespace {

void expect_sorted_and_distinct(const char* chip, const char* what, const Setting* s, int n) {
  std::set<int> bits;
  for (int i = 0; i < n; ++i) {
    if (i > 0) {
      EXPECT_LT(s[i - 1].value, s[i].value) << chip << " " << what << " " << i;
    }
    EXPECT_GT(s[i].value, 0.0f) << chip << " " << what << " " << i;
    EXPECT_TRUE(bits.insert(s[i].bits).second) << chip << " " << what << " bits repeat at " << i;
  }
}

TEST(ChipCatalog, EveryChipIsConsistent) {
  std::set<std::string> names;
  for (const ChipSpec* c : kCatalog) {
    ASSERT_NE(c->name, nullptr);
    EXPECT_TRUE(names.insert(c->name).second) << c->name << " twice";
    EXPECT_EQ(find_chip(c->name), c);
    EXPECT_TRUE(c->on_i2c || c->on_spi || on_serial(*c)) << c->name;
    if (on_serial(*c)) {
      EXPECT_FALSE(c->on_i2c || c->on_spi) << c->name << ": a servo is on a serial bus only";
      EXPECT_TRUE(c->servo_protocol == 1 || c->servo_protocol == 2) << c->name;
      EXPECT_GT(c->model_number, 0u) << c->name;
      EXPECT_TRUE(c->goal_max == 1023u || c->goal_max == 4095u) << c->name;
      EXPECT_LE(c->default_baud, c->max_clock_hz) << c->name;
    }
    if (c->on_i2c) {
      EXPECT_TRUE(c->default_address >= 0x08 && c->default_address <= 0x77) << c->name;
    }
    if (c->on_spi) {
      EXPECT_LE(c->spi_mode, 3) << c->name;
    }
    EXPECT_GT(c->max_clock_hz, 0u) << c->name;

    ASSERT_GT(c->channel_count, 0) << c->name;
    EXPECT_LE(c->channel_count, fw::drivers::kMaxChipChannels) << c->name;
    std::set<std::string> channels;
    for (int i = 0; i < c->channel_count; ++i) {
      EXPECT_TRUE(channels.insert(c->channel_names[i]).second) << c->name << " channel " << c->channel_names[i];
      EXPECT_GT(std::strlen(c->channel_units[i]), 0u) << c->name;
    }

    // A range key exactly when the chip has ranges, and settings as data.
    EXPECT_EQ(c->range_unit != nullptr, c->range_count > 0) << c->name;
    EXPECT_EQ(c->ranges != nullptr, c->range_count > 0) << c->name;
    EXPECT_EQ(c->rates != nullptr, c->rate_count > 0) << c->name;
    expect_sorted_and_distinct(c->name, "range", c->ranges, c->range_count);
    expect_sorted_and_distinct(c->name, "rate", c->rates, c->rate_count);
    for (int i = 0; i < c->rate_count; ++i) EXPECT_EQ(setting_index(c->rates, c->rate_count, c->rates[i]), i);
  }
  EXPECT_EQ(find_chip("lis3mdl "), nullptr);
  EXPECT_EQ(find_chip("bmp388"), nullptr);
}

// The declared counts are the arrays' sizes (counts written by hand).
template <size_t Channels, size_t Units>
void expect_channels(const ChipSpec& c, const char* const (&)[Channels], const char* const (&)[Units]) {
  EXPECT_EQ(c.channel_count, static_cast<int>(Channels)) << c.name;
  EXPECT_EQ(c.channel_count, static_cast<int>(Units)) << c.name;
}
template <size_t Ranges, size_t Rates>
void expect_settings(const ChipSpec& c, const Setting (&)[Ranges], const Setting (&)[Rates]) {
  EXPECT_EQ(c.range_count, static_cast<int>(Ranges)) << c.name;
  EXPECT_EQ(c.rate_count, static_cast<int>(Rates)) << c.name;
}

TEST(ChipCatalog, CountsAreTheArraysSizes) {
  expect_channels(kLis3mdl, lis3mdl::kChannels, lis3mdl::kUnits);
  expect_settings(kLis3mdl, lis3mdl::kRanges, lis3mdl::kRates);
  expect_channels(kLsm303dlhcMag, lsm303dlhc_mag::kChannels, lsm303dlhc_mag::kUnits);
  expect_settings(kLsm303dlhcMag, lsm303dlhc_mag::kRanges, lsm303dlhc_mag::kRates);
  expect_channels(kDps310, dps310::kChannels, dps310::kUnits);
  EXPECT_EQ(kDps310.rate_count, static_cast<int>(sizeof(dps310::kRates) / sizeof(dps310::kRates[0])));
  expect_channels(kMax1111, max1111::kChannels, max1111::kUnits);
  for (const ChipSpec* servo : {&kRx64, &kMx28, &kAx12a, &kXl430W250, &kXm430W350}) {
    expect_channels(*servo, dynamixel::kChannels, dynamixel::kUnits);
    EXPECT_EQ(servo->rate_count, static_cast<int>(std::size(dynamixel::kReadRates))) << servo->name;
  }
  EXPECT_EQ(sizeof(kCatalog) / sizeof(kCatalog[0]), 9u) << "a chip added: its counts checked here too";
}

}  // namespace
}  // namespace nlsoft::chips
