// The DPS310 driver against a register-level fake of the chip: the
// datasheet's chip, and QEMU's dps310 model with its fixed readings.
#include "firmware/drivers/dps310.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "chip_checks.hpp"
#include "fake_bus.hpp"

namespace nlsoft::fw::drivers {
namespace {

// QEMU 7.2's dps310 model after reset (hw/sensor/dps310.c): registers 0x00
// to 0x32. Results PSR 0xFE2FEE, TMP 0x0269A6; coefficients from 0x10;
// COEF_SRCE 0x90 (the MEMS element's sensor).
constexpr uint8_t kQemuRegisters[] = {
    0xfe, 0x2f, 0xee, 0x02, 0x69, 0xa6, 0x00, 0x80, 0xc7, 0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x0e,
    0x1e, 0xdd, 0x13, 0xca, 0x5f, 0x21, 0x52, 0xf9, 0xc6, 0x04, 0xd1, 0xdb, 0x47, 0x00, 0x5b, 0xfb, 0x3a,
    0x00, 0x00, 0x20, 0x49, 0x4e, 0xa5, 0x90, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x60, 0x15, 0x02};

// The address always advances; SPI's bit 7 reads. `qemu`: MEAS_CFG is
// stored whole and the ready flags never clear, as in QEMU's model;
// otherwise as the datasheet: its flags are read-only, COEF_RDY and
// SENSOR_RDY rise after `reads_until_ready` reads of MEAS_CFG, and reading
// a result clears its ready flag.
class FakeDps310 final : public fake::RegisterChip {
 public:
  explicit FakeDps310(bool qemu) : RegisterChip({0x80, 0, 0, true}), qemu_(qemu) {
    for (size_t i = 0; i < sizeof(kQemuRegisters); ++i) regs[i] = kQemuRegisters[i];
    regs[0x08] = 0xF0;
  }
  int reads_until_ready = 0;
  int meas_cfg_reads = 0;

  void result(int32_t pressure, int32_t temperature) {
    put24(0x00, pressure);
    put24(0x03, temperature);
    regs[0x08] |= 0x30;
  }

 protected:
  uint8_t read_register(uint8_t reg) override {
    if (reg == 0x08) {
      ++meas_cfg_reads;
      if (reads_until_ready > 0 && --reads_until_ready == 0) regs[0x08] |= 0xC0;
    }
    const uint8_t v = regs[reg];
    if (!qemu_ && reg == 0x00) regs[0x08] &= static_cast<uint8_t>(~0x10);
    if (!qemu_ && reg == 0x03) regs[0x08] &= static_cast<uint8_t>(~0x20);
    return v;
  }
  void write_register(uint8_t reg, uint8_t value) override {
    if (reg == 0x08 && !qemu_)
      regs[0x08] = static_cast<uint8_t>((regs[0x08] & 0xF0) | (value & 0x07));
    else if (reg >= 0x06 && reg <= 0x09)
      regs[reg] = value;
  }

 private:
  void put24(uint8_t reg, int32_t v) {
    const auto u = static_cast<uint32_t>(v);
    regs[reg] = static_cast<uint8_t>(u >> 16);
    regs[reg + 1u] = static_cast<uint8_t>(u >> 8);
    regs[reg + 2u] = static_cast<uint8_t>(u);
  }
  bool qemu_;
};

using O = Dps310::Oversampling;
constexpr chips::Setting kHz8 = chips::dps310::kRates[3];

struct I2cRig {
  fake::I2c bus;
  FakeDps310 chip;
  Dps310 driver;
  explicit I2cRig(bool qemu, O p = O::k1, O t = O::k1, chips::Setting rate = kHz8)
      : chip(qemu), driver(Dps310::Config{BusAttachment{&bus, 0x77, nullptr, {}}, rate, p, t}) {
    bus.attach(0x77, &chip);
  }
};

struct SpiRig {
  fake::Spi bus;
  FakeDps310 chip{false};
  Dps310 driver;
  SpiRig() : driver(Dps310::Config{BusAttachment{nullptr, 0, &bus, SpiTarget{1, 3, 1000000}}, kHz8, O::k1, O::k1}) {
    bus.attach(1, &chip);
  }
};

using Writes = std::vector<std::pair<uint8_t, uint8_t>>;

// QEMU's fixed results through its coefficients, worked in double from the
// datasheet's formulas at single oversampling (kP = kT = 524288): c0 225,
// c1 -291, c00 81061, c10 -57006, c01 -1594, c11 1233, c20 -9401, c21 91,
// c30 -1222; Praw -118802, Traw 158118.
void expect_qemus_reading(Dps310& driver) {
  const check::Reading out = check::read_ok(driver);
  EXPECT_NEAR(out[0], 92946.311, 0.02);
  EXPECT_NEAR(out[1], 24.7384, 1e-4);
}

TEST(Dps310, QemusFixedReadingsThroughItsCoefficients) {
  I2cRig rig(true);
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  expect_qemus_reading(rig.driver);
}

TEST(Dps310, ConfigurationOrderAndBytesOnQemusModel) {
  I2cRig rig(true);
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  // No retrim (0x32 bit 1 set); CFG_REG no shift; PRS_CFG 8 Hz, 1x; TMP_CFG
  // the external sensor COEF_SRCE names, 8 Hz, 1x; then MEAS_CFG background
  // pressure and temperature, written over what it read so the model keeps
  // its ready flags.
  EXPECT_EQ(rig.chip.writes, (Writes{{0x09, 0x00}, {0x06, 0x30}, {0x07, 0xB0}, {0x08, 0xF7}}));
  expect_qemus_reading(rig.driver);
  expect_qemus_reading(rig.driver);  // the model never clears its flags
}

TEST(Dps310, CoefficientsAreTwosComplementFieldsOf12_20And16Bits) {
  const Dps310::Coefficients q = Dps310::decode_coefficients(&kQemuRegisters[0x10]);
  EXPECT_EQ(q.c0, 225);
  EXPECT_EQ(q.c1, -291);
  EXPECT_EQ(q.c00, 81061);
  EXPECT_EQ(q.c10, -57006);
  EXPECT_EQ(q.c01, -1594);
  EXPECT_EQ(q.c11, 1233);
  EXPECT_EQ(q.c20, -9401);
  EXPECT_EQ(q.c21, 91);
  EXPECT_EQ(q.c30, -1222);
  const uint8_t edges[18] = {0x80, 0x07, 0xFF, 0x80, 0x00, 0x07, 0xFF, 0xFF, 0x80, 0x00, 0x7F, 0xFF,
                             0xFF, 0xFF, 0x00, 0x01, 0x80, 0x01};
  const Dps310::Coefficients e = Dps310::decode_coefficients(edges);
  EXPECT_EQ(e.c0, -2048);
  EXPECT_EQ(e.c1, 2047);
  EXPECT_EQ(e.c00, -524288);
  EXPECT_EQ(e.c10, 524287);
  EXPECT_EQ(e.c01, -32768);
  EXPECT_EQ(e.c11, 32767);
  EXPECT_EQ(e.c20, -1);
  EXPECT_EQ(e.c21, 1);
  EXPECT_EQ(e.c30, -32767);
}

TEST(Dps310, OversamplingAboveEightSetsTheShiftBitAndItsScaleFactor) {
  I2cRig rig(true, O::k64, O::k16);
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  EXPECT_EQ(rig.chip.regs[0x06], 0x36);
  EXPECT_EQ(rig.chip.regs[0x07], 0xB4);
  EXPECT_EQ(rig.chip.regs[0x09], 0x0C);
  const check::Reading out = check::read_ok(rig.driver);
  // The same raw results scaled by kP(64) = 1040384 and kT(16) = 253952.
  const double p = -118802.0 / 1040384.0, t = 158118.0 / 253952.0;
  EXPECT_NEAR(out[0], 81061 + p * (-57006 + p * (-9401 + p * -1222)) + t * -1594 + t * p * (1233 + p * 91), 0.02);
  EXPECT_NEAR(out[1], 225 * 0.5 + -291 * t, 1e-4);

  I2cRig eight(true, O::k8, O::k8);
  ASSERT_EQ(eight.driver.begin(), ChipStatus::kOk);
  EXPECT_EQ(eight.chip.regs[0x09], 0x00) << "8 times needs no shift";
}

TEST(Dps310, TheTemperatureSensorFollowsTheCoefficientsSource) {
  I2cRig rig(false);
  rig.chip.regs[0x28] = 0x00;  // coefficients made with the ASIC's sensor
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  EXPECT_EQ(rig.chip.regs[0x07], 0x30);
}

TEST(Dps310, AChipWhoseTemperatureTrimIsWrongIsRetrimmedFirst) {
  I2cRig rig(false);
  rig.chip.regs[0x32] = 0x00;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  const Writes retrim{{0x0E, 0xA5}, {0x0F, 0x96}, {0x62, 0x02}, {0x0E, 0x00}, {0x0F, 0x00}};
  ASSERT_GE(rig.chip.writes.size(), retrim.size());
  EXPECT_EQ(Writes(rig.chip.writes.begin(), rig.chip.writes.begin() + 5), retrim);
}

TEST(Dps310, NoNewPressureIsNotReadyAndLeavesOutAlone) {
  I2cRig rig(false);
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.result(0, 0);
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[0], 81061.0, 1e-2) << "raw 0: c00 alone";
  EXPECT_NEAR(out[1], 112.5, 1e-4) << "raw 0: c0 / 2 alone";
  check::expect_refused(rig.driver, ChipStatus::kNotReady);
}

TEST(Dps310, BeginWaitsABoundedTimeForTheCoefficientsAndCanBeRetried) {
  I2cRig rig(false);
  rig.chip.regs[0x08] = 0x00;
  rig.chip.reads_until_ready = 1000;
  EXPECT_EQ(rig.driver.begin(), ChipStatus::kNotReady);
  EXPECT_EQ(rig.chip.meas_cfg_reads, Dps310::kReadyPolls);
  EXPECT_TRUE(rig.chip.writes.empty());
  check::expect_refused(rig.driver, ChipStatus::kNotReady);
  rig.chip.reads_until_ready = 3;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.result(-118802, 158118);
  expect_qemus_reading(rig.driver);
}

TEST(Dps310, AMissingChipIsAbsentOnI2cAndSpi) {
  I2cRig i2c(false);
  i2c.chip.present = false;
  EXPECT_EQ(i2c.driver.begin(), ChipStatus::kAbsent);
  SpiRig spi;
  spi.chip.present = false;
  EXPECT_EQ(spi.driver.begin(), ChipStatus::kAbsent);
}

TEST(Dps310, AWrongProductIdIsReported) {
  I2cRig rig(false);
  rig.chip.regs[0x0D] = 0x11;
  EXPECT_EQ(rig.driver.begin(), ChipStatus::kWrongId);
  EXPECT_TRUE(rig.chip.writes.empty());
}

TEST(Dps310, OnSpiTheSameReadings) {
  SpiRig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.result(-118802, 158118);
  expect_qemus_reading(rig.driver);
}

TEST(Dps310, AChipThatStopsAnsweringOrResetIsABusFault) {
  // A new result waits in each chip: only the silence can refuse the read.
  I2cRig i2c(false);
  i2c.chip.result(1, 1);
  check::expect_fault_once_silent(i2c.driver, i2c.chip);
  SpiRig spi;
  spi.chip.result(1, 1);
  check::expect_fault_once_silent(spi.driver, spi.chip);  // MISO reads all ones
  spi.chip.miso_idle = 0x00;
  check::expect_refused(spi.driver, ChipStatus::kBusFault);

  I2cRig reset(false);
  ASSERT_EQ(reset.driver.begin(), ChipStatus::kOk);
  reset.chip.result(1, 1);
  reset.chip.regs[0x06] = 0x00;  // a brown-out: back to its reset configuration
  reset.chip.regs[0x08] = 0xF0;
  check::expect_refused(reset.driver, ChipStatus::kBusFault);
}

TEST(Dps310, ARateTheChipLacksOrNoBusIsRefused) {
  fake::I2c bus;
  FakeDps310 chip(false);
  bus.attach(0x77, &chip);
  const BusAttachment on_i2c{&bus, 0x77, nullptr, {}};
  EXPECT_EQ(Dps310({on_i2c, chips::Setting{3.0f, 0x20}, O::k1, O::k1}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(Dps310({on_i2c, kHz8, static_cast<O>(8), O::k1}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(Dps310({BusAttachment{}, kHz8, O::k1, O::k1}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(chip.transactions, 0);
}

}  // namespace
}  // namespace nlsoft::fw::drivers
