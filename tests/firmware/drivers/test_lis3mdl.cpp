// The LIS3MDL driver against a register-level fake of the chip on SPI and I²C.
#include "firmware/drivers/lis3mdl.hpp"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "chip_checks.hpp"
#include "fake_bus.hpp"

namespace nlsoft::fw::drivers {
namespace {

namespace spec = chips::lis3mdl;

// The chip's addressing as the datasheet gives it: SPI bit 7 reads, bit 6
// advances the address; on I²C bit 7 of the sub-address advances it.
class FakeLis3mdl final : public fake::RegisterChip {
 public:
  FakeLis3mdl() : RegisterChip({0x80, 0x40, 0x80, false}) { regs[0x0F] = 0x3D; }

  // A new sample: the output registers and STATUS_REG's ZYXDA.
  void sample(int16_t x, int16_t y, int16_t z) {
    const int16_t v[3] = {x, y, z};
    for (int i = 0; i < 3; ++i) {
      regs[static_cast<size_t>(0x28 + 2 * i)] = static_cast<uint8_t>(static_cast<uint16_t>(v[i]) & 0xFF);
      regs[static_cast<size_t>(0x29 + 2 * i)] = static_cast<uint8_t>(static_cast<uint16_t>(v[i]) >> 8);
    }
    regs[0x27] |= 0x08;
  }

 protected:
  uint8_t read_register(uint8_t reg) override {
    const uint8_t v = regs[reg];
    if (reg == 0x2D) regs[0x27] &= static_cast<uint8_t>(~0x08);  // the sample read out
    return v;
  }
  void write_register(uint8_t reg, uint8_t value) override {
    if (reg == 0x0F || reg == 0x27 || (reg >= 0x28 && reg <= 0x2F)) return;  // read-only
    regs[reg] = value;
  }
};

constexpr chips::Setting kGauss16 = spec::kRanges[3];
constexpr chips::Setting kHz1000 = spec::kRates[11];

struct SpiRig {
  fake::Spi bus;
  FakeLis3mdl chip;
  Lis3mdl driver;
  explicit SpiRig(chips::Setting range = kGauss16, chips::Setting rate = kHz1000)
      : driver(Lis3mdl::Config{BusAttachment{nullptr, 0, &bus, SpiTarget{2, 3, 1000000}}, range, rate}) {
    bus.attach(2, &chip);
  }
};

struct I2cRig {
  fake::I2c bus;
  FakeLis3mdl chip;
  Lis3mdl driver;
  explicit I2cRig(chips::Setting range = kGauss16)
      : driver(Lis3mdl::Config{BusAttachment{&bus, 0x1C, nullptr, {}}, range, kHz1000}) {
    bus.attach(0x1C, &chip);
  }
};

using Writes = std::vector<std::pair<uint8_t, uint8_t>>;

TEST(Lis3mdl, ThePapersSettingsAreCtrlReg1To5InOneBurst) {
  SpiRig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  // CTRL_REG1 0x02 (FAST_ODR, OM low-power: 1 kHz), CTRL_REG2 0x60 (±16
  // gauss), CTRL_REG3 0 (continuous), CTRL_REG4 OMZ = OM = 0, CTRL_REG5 BDU.
  EXPECT_EQ(rig.chip.writes, (Writes{{0x20, 0x02}, {0x21, 0x60}, {0x22, 0x00}, {0x23, 0x00}, {0x24, 0x40}}));
  EXPECT_EQ(rig.chip.multi_byte_writes, 1);
  // WHO_AM_I, the burst, its read-back.
  EXPECT_EQ(rig.chip.transactions, 3);
  EXPECT_EQ(rig.bus.last_target.cs, 2);
  EXPECT_EQ(rig.bus.last_target.mode, 3);
}

TEST(Lis3mdl, AFastRateSetsZsOperatingModeToXAndYs) {
  SpiRig rig(spec::kRanges[0], spec::kRates[8]);  // ±4 gauss, 155 Hz: OM ultra-high performance
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  EXPECT_EQ(rig.chip.regs[0x20], 0x62);
  EXPECT_EQ(rig.chip.regs[0x21], 0x00);
  EXPECT_EQ(rig.chip.regs[0x23], 0x0C);
}

TEST(Lis3mdl, ASlowRateUsesTheDataRateBits) {
  SpiRig rig(spec::kRanges[1], spec::kRates[7]);  // ±8 gauss, 80 Hz
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  EXPECT_EQ(rig.chip.regs[0x20], 0x1C);
  EXPECT_EQ(rig.chip.regs[0x21], 0x20);
  EXPECT_EQ(rig.chip.regs[0x23], 0x00);
}

// The datasheet's sensitivities, LSB per gauss, per range in kRanges' order.
constexpr double kLsbPerGauss[] = {6842.0, 3421.0, 2281.0, 1711.0};

TEST(Lis3mdl, BurstReadsDecodeWithEachRangesSensitivityAndSign) {
  for (int r = 0; r < 4; ++r) {
    SpiRig rig(spec::kRanges[r]);
    ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
    const int16_t x = static_cast<int16_t>(kLsbPerGauss[r]), y = -1234, z = 32767;
    rig.chip.sample(x, y, z);
    const int before = rig.chip.transactions;
    const check::Reading out = check::read_ok(rig.driver);
    EXPECT_EQ(rig.chip.transactions - before, 1) << "status and the six bytes in one transaction";
    EXPECT_NEAR(out[0], 100.0, 1e-4) << "1 gauss = 100 uT at range " << r;
    EXPECT_NEAR(out[1], -1234 * 100.0 / kLsbPerGauss[r], 1e-3);
    EXPECT_NEAR(out[2], 32767 * 100.0 / kLsbPerGauss[r], 1e-2);
  }
}

TEST(Lis3mdl, NegativeFullScaleReadsAsTheRangesMinimum) {
  SpiRig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.sample(-32768, -1, 0);
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[0], -32768 * 100.0 / 1711.0, 1e-2);  // -1915.1 uT, just past -16 gauss
  EXPECT_NEAR(out[1], -100.0 / 1711.0, 1e-6);
  EXPECT_EQ(out[2], 0.0f);
}

TEST(Lis3mdl, NoNewSampleIsNotReadyAndLeavesOutAlone) {
  SpiRig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.sample(1711, 200, 300);
  EXPECT_NEAR(check::read_ok(rig.driver)[0], 100.0, 1e-4);
  check::expect_refused(rig.driver, ChipStatus::kNotReady);
}

TEST(Lis3mdl, AMissingChipIsAbsentOnEitherMisoLevelAndOnI2c) {
  for (uint8_t idle : {uint8_t{0xFF}, uint8_t{0x00}}) {
    SpiRig rig;
    rig.chip.present = false;
    rig.chip.miso_idle = idle;
    EXPECT_EQ(rig.driver.begin(), ChipStatus::kAbsent) << int{idle};
    check::expect_refused(rig.driver, ChipStatus::kAbsent);
  }
  I2cRig rig;
  rig.chip.present = false;
  EXPECT_EQ(rig.driver.begin(), ChipStatus::kAbsent);
}

TEST(Lis3mdl, AWrongIdentityIsReportedAndNothingIsWritten) {
  SpiRig rig;
  rig.chip.regs[0x0F] = 0x33;  // an LIS3DH's WHO_AM_I
  EXPECT_EQ(rig.driver.begin(), ChipStatus::kWrongId);
  EXPECT_TRUE(rig.chip.writes.empty());
}

TEST(Lis3mdl, AChipThatStopsAnsweringIsABusFaultNotAReading) {
  SpiRig spi;
  check::expect_fault_once_silent(spi.driver, spi.chip);
  spi.chip.miso_idle = 0x00;
  check::expect_refused(spi.driver, ChipStatus::kBusFault);
  I2cRig i2c;
  check::expect_fault_once_silent(i2c.driver, i2c.chip);
}

TEST(Lis3mdl, ALiveChipAnsweringAllOnesIsStillRead) {
  // Every bit set is a legal frame (overrun flags, -1 LSB on each axis): the
  // driver asks WHO_AM_I before calling it a dead bus.
  SpiRig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.sample(-1, -1, -1);
  rig.chip.regs[0x27] = 0xFF;
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[0], -100.0 / 1711.0, 1e-6);
}

TEST(Lis3mdl, ASpiControllerFaultIsABusFault) {
  SpiRig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.bus.status = BusStatus::kTimeout;
  check::expect_refused(rig.driver, ChipStatus::kBusFault);
}

TEST(Lis3mdl, AFailedBeginCanBeRetried) {
  SpiRig rig;
  rig.chip.present = false;
  EXPECT_EQ(rig.driver.begin(), ChipStatus::kAbsent);
  rig.chip.present = true;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.sample(1711, 0, 0);
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[0], 100.0, 1e-4);
}

TEST(Lis3mdl, OnI2cTheBurstsSetTheAutoIncrementBit) {
  // Without bit 7 the fake answers one register over and over: the decoded
  // axes would all be x's low byte.
  I2cRig rig(spec::kRanges[0]);
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  EXPECT_EQ(rig.chip.regs[0x24], 0x40);
  rig.chip.sample(6842, -6842, 3421);
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[0], 100.0, 1e-4);
  EXPECT_NEAR(out[1], -100.0, 1e-4);
  EXPECT_NEAR(out[2], 50.0, 1e-4);
}

TEST(Lis3mdl, ARangeOrRateTheChipLacksOrABusLessConfigIsRefused) {
  fake::Spi bus;
  FakeLis3mdl chip;
  bus.attach(0, &chip);
  const BusAttachment on_spi{nullptr, 0, &bus, {}};
  EXPECT_EQ(Lis3mdl({on_spi, chips::Setting{16.0f, 0x40}, kHz1000}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(Lis3mdl({on_spi, kGauss16, chips::Setting{2000.0f, 0x02}}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(Lis3mdl({BusAttachment{}, kGauss16, kHz1000}).begin(), ChipStatus::kBadConfig);
  fake::I2c i2c;
  EXPECT_EQ(Lis3mdl({BusAttachment{&i2c, 0x1C, &bus, {}}, kGauss16, kHz1000}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(chip.transactions, 0);
}

}  // namespace
}  // namespace nlsoft::fw::drivers
