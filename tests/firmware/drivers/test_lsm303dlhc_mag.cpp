// The LSM303DLHC magnetometer driver against a register-level fake of the
// chip as the datasheet and QEMU's lsm303dlhc_mag model describe it.
#include "firmware/drivers/lsm303dlhc_mag.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "chip_checks.hpp"
#include "fake_bus.hpp"

namespace nlsoft::fw::drivers {
namespace {

namespace spec = chips::lsm303dlhc_mag;

// LSB per gauss per gain code GN = 1..7 (datasheet; QEMU's model has the
// same tables): x and y share one, z has its own.
constexpr int kXyGain[] = {1100, 855, 670, 450, 400, 330, 230};
constexpr int kZGain[] = {980, 760, 600, 400, 355, 295, 205};

// Reads always advance the pointer, wrapping 0x08 -> 0x03 and 0x0C -> 0x00;
// like QEMU's model, every data byte of a write lands in the one register
// the write addressed.
class FakeLsm303dlhcMag final : public fake::RegisterChip {
 public:
  FakeLsm303dlhcMag() : RegisterChip({0, 0, 0, true}) {
    regs[0x00] = 0x10;  // reset values: 15 Hz, ±1.3 gauss, sleep
    regs[0x01] = 0x20;
    regs[0x02] = 0x03;
    regs[0x09] = 0x01;
    regs[0x0A] = 'H';
    regs[0x0B] = '4';
    regs[0x0C] = '3';
  }

  // Raw output registers, big-endian, x then z then y from 0x03.
  void raw(int16_t x, int16_t y, int16_t z) {
    put(0x03, x);
    put(0x05, z);
    put(0x07, y);
  }
  // QEMU's mag-x/y/z properties: 1 = 0.001 uT, stored as whole LSB at the
  // gain CRB_REG_M holds.
  void field_milli_ut(int64_t x, int64_t y, int64_t z) {
    const int gn = regs[0x01] >> 5;
    raw(static_cast<int16_t>(x * kXyGain[gn - 1] / 100000), static_cast<int16_t>(y * kXyGain[gn - 1] / 100000),
        static_cast<int16_t>(z * kZGain[gn - 1] / 100000));
  }

 protected:
  uint8_t next(uint8_t reg) const override {
    if (reg == 0x08) return 0x03;
    if (reg == 0x0C) return 0x00;
    return static_cast<uint8_t>(reg + 1);
  }
  bool write_increments(bool) const override { return false; }
  void write_register(uint8_t reg, uint8_t value) override {
    if (reg <= 0x02) regs[reg] = value;  // the rest is read-only
  }

 private:
  void put(uint8_t reg, int16_t v) {
    regs[reg] = static_cast<uint8_t>(static_cast<uint16_t>(v) >> 8);
    regs[reg + 1u] = static_cast<uint8_t>(static_cast<uint16_t>(v) & 0xFF);
  }
};

struct Rig {
  fake::I2c bus;
  FakeLsm303dlhcMag chip;
  Lsm303dlhcMag driver;
  explicit Rig(int range = 0, int rate = 4)
      : driver(Lsm303dlhcMag::Config{&bus, 0x1E, spec::kRanges[range], spec::kRates[rate]}) {
    bus.attach(0x1E, &chip);
  }
};

using Writes = std::vector<std::pair<uint8_t, uint8_t>>;

TEST(Lsm303dlhcMag, ConfigurationIsRateGainAndContinuousOneRegisterPerWrite) {
  Rig rig(0, 4);  // ±1.3 gauss, 15 Hz
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  EXPECT_EQ(rig.chip.writes, (Writes{{0x00, 0x10}, {0x01, 0x20}, {0x02, 0x00}}));
  EXPECT_EQ(rig.chip.multi_byte_writes, 0) << "QEMU's model would put every byte in one register";

  Rig fast(6, 7);  // ±8.1 gauss, 220 Hz
  ASSERT_EQ(fast.driver.begin(), ChipStatus::kOk);
  EXPECT_EQ(fast.chip.writes, (Writes{{0x00, 0x1C}, {0x01, 0xE0}, {0x02, 0x00}}));
}

TEST(Lsm303dlhcMag, OutputsAreBigEndianXZYWithSeparateXyAndZSensitivity) {
  for (int g = 0; g < 7; ++g) {
    Rig rig(g);
    ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
    // One gauss on x, minus half a gauss on y, two on z (where the 12-bit range allows).
    rig.chip.raw(static_cast<int16_t>(kXyGain[g]), static_cast<int16_t>(-kXyGain[g] / 2),
                 static_cast<int16_t>(kZGain[g] <= 1023 ? 2 * kZGain[g] : kZGain[g]));
    const check::Reading out = check::read_ok(rig.driver);
    EXPECT_NEAR(out[0], 100.0, 1e-4) << "gain " << g;
    EXPECT_NEAR(out[1], (-kXyGain[g] / 2) * 100.0 / kXyGain[g], 1e-4);
    EXPECT_NEAR(out[2], kZGain[g] <= 1023 ? 200.0 : 100.0, 1e-4);
  }
}

TEST(Lsm303dlhcMag, TheTwelveBitFullScaleAndItsSign) {
  Rig rig(6);  // ±8.1 gauss
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.raw(-2048, 2047, -1);
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[0], -2048 * 100.0 / 230.0, 1e-3);
  EXPECT_NEAR(out[1], 2047 * 100.0 / 230.0, 1e-3);
  EXPECT_NEAR(out[2], -100.0 / 205.0, 1e-5);
}

TEST(Lsm303dlhcMag, QemuPropertiesReadBackInMicrotesla) {
  // The model's own test values: mag-x 100000, mag-y 150000, mag-z 50000
  // (1 = 0.001 uT) are 1, 1.5 and 0.5 gauss.
  Rig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.field_milli_ut(100000, 150000, 50000);
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[0], 100.0, 1e-4);
  EXPECT_NEAR(out[1], 150.0, 1e-4);
  EXPECT_NEAR(out[2], 50.0, 1e-4);
}

TEST(Lsm303dlhcMag, NoNewSampleIsNotReadyAndLeavesOutAlone) {
  Rig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.raw(1, 2, 3);
  rig.chip.regs[0x09] = 0x00;
  check::expect_refused(rig.driver, ChipStatus::kNotReady);
}

TEST(Lsm303dlhcMag, AMissingChipIsAbsent) {
  Rig rig;
  rig.chip.present = false;
  EXPECT_EQ(rig.driver.begin(), ChipStatus::kAbsent);
  check::expect_refused(rig.driver, ChipStatus::kAbsent);
}

TEST(Lsm303dlhcMag, EachIdentityRegisterIsChecked) {
  for (uint8_t reg : {uint8_t{0x0A}, uint8_t{0x0B}, uint8_t{0x0C}}) {
    Rig rig;
    rig.chip.regs[reg] = 'X';
    EXPECT_EQ(rig.driver.begin(), ChipStatus::kWrongId) << int{reg};
    EXPECT_TRUE(rig.chip.writes.empty());
  }
}

TEST(Lsm303dlhcMag, AChipThatStopsAnsweringIsABusFault) {
  Rig rig;
  check::expect_fault_once_silent(rig.driver, rig.chip);
}

TEST(Lsm303dlhcMag, AChipThatResetItselfIsABusFaultNotItsLastSample) {
  Rig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.raw(1100, 0, 0);
  rig.chip.regs[0x02] = 0x03;  // MR_REG_M's reset value: sleep
  check::expect_refused(rig.driver, ChipStatus::kBusFault);
}

TEST(Lsm303dlhcMag, AFailedBeginCanBeRetried) {
  Rig rig;
  rig.chip.regs[0x0A] = 0;
  EXPECT_EQ(rig.driver.begin(), ChipStatus::kWrongId);
  rig.chip.regs[0x0A] = 'H';
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.raw(1100, 0, 0);
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[0], 100.0, 1e-4);
}

TEST(Lsm303dlhcMag, AGainTheChipLacksOrNoBusIsRefused) {
  fake::I2c bus;
  FakeLsm303dlhcMag chip;
  bus.attach(0x1E, &chip);
  EXPECT_EQ(Lsm303dlhcMag({&bus, 0x1E, chips::Setting{1.3f, 0x00}, spec::kRates[0]}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(Lsm303dlhcMag({nullptr, 0x1E, spec::kRanges[0], spec::kRates[0]}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(chip.transactions, 0);
}

}  // namespace
}  // namespace nlsoft::fw::drivers
