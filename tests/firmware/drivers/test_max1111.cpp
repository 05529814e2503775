// The MAX1111 driver against a fake of the ADC's serial frame.
#include "firmware/drivers/max1111.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "chip_checks.hpp"
#include "fake_bus.hpp"

namespace nlsoft::fw::drivers {
namespace {

// The ADC's 24-clock external-clock frame as the datasheet draws it and
// QEMU's max111x model answers it: a byte with START (bit 7) is a control
// byte; the two bytes after it carry 0 0 D7..D2 and D1 D0 0 0 0 0 0 0.
// Channels by SEL2 (low bit) and SEL1 (high bit); SEL0 is unused on the
// 4-input part.
class FakeMax1111 final : public fake::Device {
 public:
  uint8_t codes[4] = {};
  std::vector<uint8_t> controls;  // every control byte, in order
  int other_modes = 0;            // control bytes not unipolar, single-ended, external clock

  BusStatus i2c(const uint8_t*, size_t, uint8_t*, size_t) override { return BusStatus::kNack; }

  void spi(const uint8_t* tx, uint8_t* rx, size_t n) override {
    int cycle = 3;
    uint8_t code = 0;
    for (size_t i = 0; i < n; ++i) {
      if (tx[i] & 0x80) {
        controls.push_back(tx[i]);
        if ((tx[i] & 0x0F) != 0x0F) ++other_modes;
        code = codes[((tx[i] >> 6) & 1) | (((tx[i] >> 5) & 1) << 1)];
        cycle = 0;
      }
      rx[i] = static_cast<uint8_t>(cycle == 1 ? code >> 2 : cycle == 2 ? code << 6 : 0);
      ++cycle;
    }
  }
};

struct Rig {
  fake::Spi bus;
  FakeMax1111 chip;
  Max1111 driver;
  explicit Rig(float reference = Max1111::kInternalReferenceVolts)
      : driver(Max1111::Config{&bus, SpiTarget{4, 0, 500000}, reference}) {
    bus.attach(4, &chip);
  }
};

TEST(Max1111, OneTransferConvertsTheFourInputsInOrder) {
  Rig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.controls.clear();
  const int before = rig.bus.transactions;
  check::read_ok(rig.driver);
  EXPECT_EQ(rig.bus.transactions - before, 1);
  // START, SEL2 SEL1 for channels 0..3, unipolar, single-ended, powered, external clock.
  EXPECT_EQ(rig.chip.controls, (std::vector<uint8_t>{0x8F, 0xCF, 0xAF, 0xEF}));
  EXPECT_EQ(rig.chip.other_modes, 0);
  EXPECT_EQ(rig.bus.last_target.mode, 0);
}

TEST(Max1111, CodesAreVoltsOfTheReference) {
  Rig rig;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  const uint8_t codes[4] = {0, 1, 128, 255};
  for (int i = 0; i < 4; ++i) rig.chip.codes[i] = codes[i];
  check::Reading out = check::read_ok(rig.driver);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(out[i], codes[i] * 2.048 / 256.0, 1e-6) << i;  // 8 mV per code

  // QEMU's model powers up with inputs 0xF0, 0xE0, 0xD0, 0xC0 against COM = 0.
  const uint8_t qemu[4] = {0xF0, 0xE0, 0xD0, 0xC0};
  for (int i = 0; i < 4; ++i) rig.chip.codes[i] = qemu[i];
  out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[0], 1.920, 1e-6);
  EXPECT_NEAR(out[3], 1.536, 1e-6);
}

TEST(Max1111, AnExternalReferenceSetsTheFullScale) {
  Rig rig(3.3f);
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.codes[2] = 255;
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[2], 3.3 * 255.0 / 256.0, 1e-5);
}

TEST(Max1111, AllOnesOnMisoIsAnAbsentChip) {
  Rig rig;
  rig.chip.present = false;
  EXPECT_EQ(rig.driver.begin(), ChipStatus::kAbsent);
  check::expect_refused(rig.driver, ChipStatus::kAbsent);
}

// Another chip on the select line: its answer sets the framing bits.
class NotAMax1111 final : public fake::Device {
 public:
  BusStatus i2c(const uint8_t*, size_t, uint8_t*, size_t) override { return BusStatus::kNack; }
  void spi(const uint8_t*, uint8_t* rx, size_t n) override {
    for (size_t i = 0; i < n; ++i) rx[i] = static_cast<uint8_t>(0x40 + i);
  }
};

TEST(Max1111, AFrameWithItsFramingBitsSetIsNoMax1111) {
  fake::Spi bus;
  NotAMax1111 other;
  bus.attach(0, &other);
  Max1111 driver({&bus, SpiTarget{}, Max1111::kInternalReferenceVolts});
  EXPECT_EQ(driver.begin(), ChipStatus::kAbsent);
}

TEST(Max1111, AChipThatStopsAnsweringIsABusFault) {
  Rig rig;
  check::expect_fault_once_silent(rig.driver, rig.chip);
}

TEST(Max1111, AControllerFaultIsABusFaultAndBeginCanBeRetried) {
  Rig rig;
  rig.bus.status = BusStatus::kBusError;
  EXPECT_EQ(rig.driver.begin(), ChipStatus::kBusFault);
  rig.bus.status = BusStatus::kOk;
  ASSERT_EQ(rig.driver.begin(), ChipStatus::kOk);
  rig.chip.codes[1] = 100;
  const check::Reading out = check::read_ok(rig.driver);
  EXPECT_NEAR(out[1], 100 * 2.048 / 256.0, 1e-6);
}

TEST(Max1111, NoBusOrNoReferenceIsRefused) {
  fake::Spi bus;
  EXPECT_EQ(Max1111({nullptr, SpiTarget{}, 2.048f}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(Max1111({&bus, SpiTarget{}, 0.0f}).begin(), ChipStatus::kBadConfig);
  EXPECT_EQ(bus.transactions, 0);
}

}  // namespace
}  // namespace nlsoft::fw::drivers
