// The status bar's words on the sensor chips: SENSOR_HEALTH's invalid
// channels named as the rig file names them, in channel order.
#include <gtest/gtest.h>

#include "app/tui/status_bar.hpp"

namespace nlsoft::console::tui {
namespace {

TEST(StatusBar, InvalidSensorChannelsAreNamedInChannelOrder) {
  const std::vector<std::string> names = {"b1x", "b1y", "b1z", "b2x", "b2y", "b2z"};
  EXPECT_EQ(invalid_sensors_words(0u, names), "");
  EXPECT_EQ(invalid_sensors_words(0x7u, names), "sensors invalid: b1x b1y b1z");
  EXPECT_EQ(invalid_sensors_words(0x28u, names), "sensors invalid: b2x b2z");
  // A bit past the rig's sensors (a firmware built from another file) is
  // still shown, by its channel number.
  EXPECT_EQ(invalid_sensors_words(1u << 31 | 1u, names), "sensors invalid: b1x l31");
}

}  // namespace
}  // namespace nlsoft::console::tui
