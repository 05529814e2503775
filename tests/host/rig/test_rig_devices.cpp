// Sensor chips on the board's buses ([[device]], [[sensor]] source =
// "device"): each fault at its file:line and key, with what the chip or the
// board offers instead; a good file's devices as the image will get them.
#include <gtest/gtest.h>

#include <string>

#include "host/rig/rig.hpp"
#include "../../support/rig_with_chips.hpp"
#include "rig_text.hpp"

namespace nlsoft::host {
namespace {

using rig_text::expect_error;
using rig_text::line_of;

const char* const kBase = test::kRigWithChips;

std::string edit(const std::string& from, const std::string& to, int nth = 1, std::string text = kBase) {
  return rig_text::replaced(std::move(text), from, to, nth);
}
int line(const std::string& needle, int nth = 1) { return line_of(kBase, needle, nth); }

TEST(RigDevices, AGoodFileGivesEachDeviceItsBusAndRegisterBits) {
  const Rig r = parse_rig(kBase, "my.toml");
  ASSERT_EQ(r.devices.size(), 3u);
  const RigDevice& tip = r.devices[0];
  EXPECT_EQ(tip.chip->name, std::string("lsm303dlhc_mag"));
  EXPECT_EQ(tip.kind, BusKind::I2c);
  EXPECT_EQ(tip.bus_index, 0);
  EXPECT_EQ(tip.address, 0x1e);
  EXPECT_EQ(tip.clock_hz, 100000u);  // standard-mode I2C when not given
  EXPECT_EQ(tip.range_bits, 0x20);   // CRB_REG_M GN = 001: ±1.3 gauss
  EXPECT_EQ(tip.rate_bits, 0x18);    // CRA_REG_M DO = 110: 75 Hz
  const RigDevice& air = r.devices[1];
  EXPECT_EQ(air.address, 0x77);      // the chip's usual strap when not given
  EXPECT_EQ(air.range, 0.0);         // a DPS310 has no range setting
  EXPECT_EQ(air.rate_bits, 0x40);
  const RigDevice& ring = r.devices[2];
  EXPECT_EQ(ring.kind, BusKind::Spi);
  EXPECT_EQ(ring.bus_index, 1);
  EXPECT_EQ(ring.cs, "PA8");
  EXPECT_EQ(ring.cs_index, 1);  // the board's chip selects: PB12, PA8, ...
  EXPECT_EQ(ring.range_bits, 0x60);  // CTRL_REG2 FS = 11: ±16 gauss, the paper's
  EXPECT_EQ(ring.rate_bits, 0x02);   // CTRL_REG1 FAST_ODR, OM = 00: 1 kHz, the paper's
  ASSERT_EQ(r.w(), 3);
  EXPECT_EQ(r.sensors[1].source, SensorSource::Device);
  EXPECT_EQ(r.sensors[1].device, 1);
  EXPECT_EQ(r.sensors[1].channel, 0);
  EXPECT_EQ(r.sensors[1].gain, 0.001);
  EXPECT_EQ(r.sensors[2].channel, 2);
  EXPECT_EQ(r.sensors[2].offset, -3.0);
  EXPECT_STREQ(sensor_source_name(r.sensors[0].source), "device");
}

TEST(RigDevices, AnUnknownChipOrBusIsRefusedWithTheKnownOnes) {
  expect_error(edit("chip = \"dps310\"", "chip = \"bmp388\""), line("chip = \"dps310\""), "[[device]] #2 chip",
               "'bmp388' is not one of: lis3mdl, lsm303dlhc_mag, dps310, max1111, rx-64, mx-28, ax-12a");
  expect_error(edit("bus = \"spi1\"", "bus = \"spi3\""), line("bus = \"spi1\""), "[[device]] #3 bus",
               "unknown bus 'spi3' on board stm32f4 (buses: i2c1, spi1, spi2, usart1, usart6)");
}

TEST(RigDevices, AChipOnABusKindItCannotUseIsRefused) {
  expect_error(edit("bus = \"i2c1\"\naddress = 0x1e", "bus = \"spi2\"\ncs = \"PA9\""), line("bus = \"i2c1\""),
               "[[device]] #1 bus", "spi2 is a SPI bus, and chip lsm303dlhc_mag talks I2C only");
  const std::string adc = edit("chip = \"dps310\"", "chip = \"max1111\"");
  expect_error(adc, line("bus = \"i2c1\"", 2), "[[device]] #2 bus",
               "i2c1 is an I2C bus, and chip max1111 talks SPI only");
}

TEST(RigDevices, AnAddressOrChipSelectIsForItsBusKindOnly) {
  expect_error(edit("cs = \"PA8\"", "address = 0x1c"), line("cs = \"PA8\""), "[[device]] #3 address",
               "an address is for an I2C bus: bus = \"spi1\" (line " + std::to_string(line("bus = \"spi1\"")) +
                   ") is SPI; give cs");
  expect_error(edit("address = 0x1e", "cs = \"PA8\""), line("address = 0x1e"), "[[device]] #1 cs",
               "a chip select is for a SPI bus");
  expect_error(edit("cs = \"PA8\"\n", ""), line("[[device]]", 3), "[[device]] #3 cs", "missing key");
  expect_error(edit("address = 0x1e", "address = 0x78"), line("address = 0x1e"), "[[device]] #1 address",
               "must be in [8, 119] (a 7-bit I2C address), not 120");
}

TEST(RigDevices, AnAddressOrChipSelectUsedTwiceNamesTheFirstUse) {
  // The DPS310 strapped to 0x1e, where the magnetometer answers.
  const std::string twice = edit("rate_hz = 16", "address = 0x1e\nrate_hz = 16");
  expect_error(twice, line_of(twice, "address = 0x1e", 2), "[[device]] #2 address",
               "i2c1 address 0x1e is already used by [[device]] #1 (line " + std::to_string(line("address = 0x1e")) + ")");
  // A PWM pin is never a chip select, nor is USART2's.
  for (const char* pin : {"PC6", "PA2"})
    expect_error(edit("cs = \"PA8\"", std::string("cs = \"") + pin + "\""), line("cs = \"PA8\""), "[[device]] #3 cs",
                 std::string("unknown chip-select pin '") + pin +
                     "' on board stm32f4 (chip-select pins: PB12, PA8, PA9, PA10, PB4, PB5, PB10, PC10)");
  // Two chips on one chip select.
  const std::string cs = edit("rate_hz = 1000", "rate_hz = 1000\n\n[[device]]\nname = \"ring2\"\nchip = \"lis3mdl\"\n"
                                                "bus = \"spi2\"\ncs = \"PA8\"\nrange = 16\nrate_hz = 1000");
  expect_error(cs, line_of(cs, "cs = \"PA8\"", 2), "[[device]] #4 cs",
               "PA8 is already used by [[device]] #3 (line " + std::to_string(line("cs = \"PA8\"")) + ")");
}

// SPI1's MISO and MOSI are ADC1_IN6/IN7's pins: a rig uses one or the other.
TEST(RigDevices, ABusTakesItsPinsFromTheAdc) {
  const std::string t = edit("channel = \"z\"\noffset = -3.0", "channel = \"z\"\noffset = -3.0\n\n[[sensor]]\nname = \"bend\"\n"
                                                            "source = \"adc\"\nadc = 7");
  expect_error(t, line_of(t, "adc = 7"), "[[sensor]] #4 adc",
               "PA7 is already used by [[device]] #3 (line " + std::to_string(line("bus = \"spi1\"")) + ")");
  EXPECT_EQ(parse_rig(rig_text::replaced(t, "adc = 7", "adc = 8"), "my.toml").w(), 4);
}

// QEMU's board: buses only, each PL022 with one chip on its own select.
TEST(RigDevices, AnMps2An386RigNamesItsShieldBuses) {
  std::string t = edit("name = \"mags\"", "name = \"mags\"\nboard = \"mps2-an386\"");
  t = rig_text::replaced(t, "pwm = \"PC6\"\n", "");
  t = rig_text::replaced(t, "bus = \"i2c1\"", "bus = \"i2c-shield1\"");
  t = rig_text::replaced(t, "bus = \"i2c1\"", "bus = \"i2c-shield1\"");
  t = rig_text::replaced(t, "bus = \"spi1\"\ncs = \"PA8\"", "bus = \"spi-shield0\"");
  const Rig r = parse_rig(t, "my.toml");
  EXPECT_EQ(r.devices[0].bus_index, 1);
  EXPECT_EQ(r.devices[2].bus_index, 2);
  expect_error(rig_text::replaced(t, "bus = \"spi-shield0\"", "bus = \"spi-shield0\"\ncs = \"PA8\""),
               line_of(t, "bus = \"spi-shield0\"") + 1, "[[device]] #3 cs",
               "bus spi-shield0 selects its one chip itself (its own select line): no cs");
}

TEST(RigDevices, AClockAboveTheChipsOrTheBussMaximumIsRefused) {
  expect_error(edit("clock_hz = 1000000", "clock_hz = 12000000"), line("clock_hz = 1000000"),
               "[[device]] #3 clock_hz", "12000000 Hz is above chip lis3mdl's maximum, 10000000 Hz");
  expect_error(edit("address = 0x1e", "address = 0x1e\nclock_hz = 1000000"), line("address = 0x1e") + 1,
               "[[device]] #1 clock_hz", "1000000 Hz is above chip lsm303dlhc_mag's maximum, 400000 Hz");
  expect_error(edit("rate_hz = 16", "rate_hz = 16\nclock_hz = 3400000"), line("rate_hz = 16") + 1,
               "[[device]] #2 clock_hz", "3400000 Hz is above bus i2c1's maximum on board stm32f4, 400000 Hz");
  expect_error(edit("clock_hz = 1000000", "clock_hz = 0"), line("clock_hz = 1000000"), "[[device]] #3 clock_hz",
               "must be in [1, 100000000] Hz, not 0");
}

TEST(RigDevices, ARangeOrRateTheChipDoesNotOfferListsWhatItOffers) {
  expect_error(edit("range = 16", "range = 10"), line("range = 16"), "[[device]] #3 range",
               "10 gauss is not a range chip lis3mdl offers (gauss: 4, 8, 12, 16)");
  expect_error(edit("rate_hz = 75", "rate_hz = 100"), line("rate_hz = 75"), "[[device]] #1 rate_hz",
               "100 Hz is not a rate_hz chip lsm303dlhc_mag offers (Hz: 0.75, 1.5, 3, 7.5, 15, 30, 75, 220)");
  expect_error(edit("rate_hz = 16", "rate_hz = 16\nrange = 2"), line("rate_hz = 16") + 1, "[[device]] #2 range",
               "chip dps310 has no range setting");
  expect_error(edit("range = 16\n", ""), line("[[device]]", 3), "[[device]] #3 range", "missing key");
}

TEST(RigDevices, ASensorNamesAKnownDeviceAndOneOfItsChipsChannels) {
  expect_error(edit("device = \"air\"", "device = \"water\""), line("device = \"air\""), "[[sensor]] #2 device",
               "no [[device]] is named 'water' (devices: tip, air, ring1)");
  expect_error(edit("channel = \"pressure\"", "channel = \"x\""), line("channel = \"pressure\""),
               "[[sensor]] #2 channel", "chip dps310 (device air) has no channel 'x' (channels: pressure, temperature)");
  const std::string adc = edit("source = \"device\"\ndevice = \"tip\"", "source = \"adc\"\nadc = 0\ndevice = \"tip\"");
  expect_error(adc, line_of(adc, "device = \"tip\""), "[[sensor]] #1 device", "only with source = \"device\"");
  expect_error(edit("device = \"tip\"", "device = \"tip\"\nadc = 1"), line("device = \"tip\"") + 1,
               "[[sensor]] #1 adc", "only with source = \"adc\"");
  expect_error(edit("gain = 0.001", "gain = 0"), line("gain = 0.001"), "[[sensor]] #2 gain", "must not be 0");
}

TEST(RigDevices, ADeviceNoSensorReadsIsRefused) {
  const std::string t = edit("device = \"air\"\nchannel = \"pressure\"", "device = \"tip\"\nchannel = \"y\"");
  expect_error(t, line("name = \"air\""), "[[device]] #2 name",
               "no [[sensor]] reads device 'air': give a sensor source = \"device\" with device = \"air\"");
}

TEST(RigDevices, ADeviceNameIsANameOfTheFile) {
  expect_error(edit("name = \"air\"", "name = \"x\""), line("name = \"air\""), "[[device]] #2 name",
               "'x' is already the name of [[output]] #1");
}

TEST(RigDevices, MoreDevicesThanTheCapacityAreRefused) {
  std::string t = kBase;
  std::string extra;
  const char* cs[] = {"PB12", "PA9", "PA10", "PB4", "PB5", "PB10"};
  for (int i = 0; i < 6; ++i)
    extra += "[[device]]\nname = \"m" + std::to_string(i) + "\"\nchip = \"lis3mdl\"\nbus = \"spi2\"\ncs = \"" +
             cs[i] + "\"\nrange = 4\nrate_hz = 80\n\n";
  t = rig_text::replaced(t, "[[sensor]]", extra + "[[sensor]]");
  expect_error(t, line_of(t, "name = \"m5\"") - 1, "[[device]] #9", "over capacity: at most 8 devices");
}

}  // namespace
}  // namespace nlsoft::host
