// What `rig check` and the script's `devices` say of each sensor chip: the
// firmware's DEVICE_STATUS beside the rig file, a chip the firmware lacks
// named, and every chip not ok counted.
#include <gtest/gtest.h>

#include <cstring>

#include "../../support/rig_with_chips.hpp"
#include "app/link/device_check.hpp"

namespace nlsoft::console {

using host::Rig;
using host::parse_rig;

namespace {

namespace p = protocol;

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

TEST(DeviceLines, EachChipAsTheFirmwareSaysAndTheFilesChipsItLacks) {
  const Rig rig = parse_rig(test::kRigWithChips, "mags.toml");
  // spi1 is the board's second bus (i2c1, spi1, spi2); PA8 its second chip select.
  const auto found = std::vector<p::DeviceStatus>{status(0, "ring1", p::DeviceState::Absent, 1, 1, p::kNoSample, 3)};
  int bad = 0;
  const std::vector<std::string> lines = device_lines(rig, found, bad);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "device ring1      lis3mdl on spi1 chip select PA8: absent, no sample yet, 3 faults");
  EXPECT_EQ(lines[1], "device tip        lsm303dlhc_mag: not in the firmware (an image built from another file?)");
  EXPECT_EQ(lines[2], "device air        dps310: not in the firmware (an image built from another file?)");
  EXPECT_EQ(bad, 3);

  const auto ok = std::vector<p::DeviceStatus>{status(0, "tip", p::DeviceState::Ok, 0, 0x1e, 12, 1),
                                               status(1, "air", p::DeviceState::WrongId, 0, 0x77, 40, 0),
                                               status(2, "ring1", p::DeviceState::Ok, 1, 1, 4, 0)};
  const std::vector<std::string> all = device_lines(rig, ok, bad);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0], "device tip        lsm303dlhc_mag on i2c1 at 0x1e: ok, latest sample 12 ms old, 1 fault");
  EXPECT_EQ(all[1], "device air        dps310 on i2c1 at 0x77: wrong id, latest sample 40 ms old, 0 faults");
  EXPECT_EQ(bad, 1);
}

}  // namespace
}  // namespace nlsoft::console
