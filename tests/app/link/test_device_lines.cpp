// What `rig check` and the script's `devices` say of each sensor chip: the
// firmware's DEVICE_STATUS beside the rig file, a chip the firmware lacks
// named, and every chip not ok counted.
#include <gtest/gtest.h>

#include <cstring>

#include "app/link/device_check.hpp"

namespace nlsoft::console {
namespace {

namespace p = protocol;

const char* kRig = R"(name = "mags"
rate_hz = 100.0
nd = 1
dd = 1

[[input]]
name = "u1"
min = 0.0
max = 1.0
neutral = 0.5
pwm = "PC6"

[[output]]
name = "x"
min = -10.0
max = 10.0

[[device]]
name = "ring1"
chip = "lis3mdl"
bus = "spi2"
cs = "PB12"
range = 16
rate_hz = 155

[[device]]
name = "tip"
chip = "lsm303dlhc_mag"
bus = "i2c1"
range = 1.3
rate_hz = 75

[[sensor]]
name = "r1x"
source = "device"
device = "ring1"
channel = "x"

[[sensor]]
name = "tx"
source = "device"
device = "tip"
channel = "x"

[controller]
Q = [1.0]
Lambda = [1.0]
s = 1e-20
b = 1e-5
r = 400.0
N = 3
Nc = 1
eps = 0.01
)";

p::DeviceStatus status(uint8_t index, const char* name, p::DeviceState state, uint8_t bus, uint8_t address,
                       uint32_t age_ms, uint32_t faults) {
  p::DeviceStatus d{};
  d.index = index;
  d.count = 1;
  d.state = uint8_t(state);
  d.bus = bus;
  d.address = address;
  d.age_ms = age_ms;
  d.faults = faults;
  std::strncpy(d.name, name, p::kMaxNameLen);
  return d;
}

TEST(DeviceLines, EachChipAsTheFirmwareSaysAndTheFilesChipItLacks) {
  const Rig rig = parse_rig(kRig, "mags.toml");
  // spi2 is the board's third bus (i2c1, spi1, spi2); PB12 its first chip select.
  const auto found = std::vector<p::DeviceStatus>{status(0, "ring1", p::DeviceState::Absent, 2, 0, p::kNoSample, 3)};
  int bad = 0;
  const std::vector<std::string> lines = device_lines(rig, found, bad);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "device ring1      lis3mdl on spi2 chip select PB12: absent, no sample yet, 3 faults");
  EXPECT_EQ(lines[1], "device tip        lsm303dlhc_mag: not in the firmware (an image built from another file?)");
  EXPECT_EQ(bad, 2);

  const auto ok = std::vector<p::DeviceStatus>{status(0, "ring1", p::DeviceState::Ok, 2, 0, 4, 0),
                                               status(1, "tip", p::DeviceState::Ok, 0, 0x1e, 12, 1)};
  EXPECT_EQ(device_lines(rig, ok, bad)[1], "device tip        lsm303dlhc_mag on i2c1 at 0x1e: ok, latest sample 12 ms old, 1 fault");
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace nlsoft::console
