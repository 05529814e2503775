// Dynamixel servos in a rig file ([[device]] on a serial bus, [[input]]
// servo = ...): the shipped tendon as the paper built it, and each fault at
// its file:line and key.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "host/rig/rig.hpp"
#include "rig_text.hpp"

namespace nlsoft::host {
namespace {

using rig_text::expect_error;
using rig_text::line_of;

std::string tendon() {
  std::ifstream in(std::string(NLSOFT_RIGS_DIR) + "/tendon.toml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
std::string edit(const std::string& from, const std::string& to, int nth = 1, std::string text = tendon()) {
  return rig_text::replaced(std::move(text), from, to, nth);
}
int line(const std::string& needle, int nth = 1) { return line_of(tendon(), needle, nth); }

TEST(RigServos, TendonDrivesItsInputsWithTwoRx64OnUsart1) {
  const Rig r = parse_rig(tendon(), "my.toml");
  ASSERT_EQ(r.devices.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const RigDevice& d = r.devices[size_t(i)];
    EXPECT_EQ(d.chip->name, std::string("rx-64"));
    EXPECT_EQ(d.chip->servo_protocol, 1);
    EXPECT_EQ(d.kind, BusKind::Serial);
    EXPECT_EQ(d.bus, "usart1");
    EXPECT_EQ(d.bus_index, 3) << "after i2c1, spi1, spi2";
    EXPECT_EQ(d.address, i + 1);
    EXPECT_EQ(d.clock_hz, 1000000u);
    EXPECT_FALSE(d.release_on_fault);
    EXPECT_EQ(r.inputs[size_t(i)].servo_device, i);
    EXPECT_EQ(r.inputs[size_t(i)].goal_per_unit, 195.57);
    EXPECT_EQ(r.inputs[size_t(i)].goal_at_neutral, 512.0);
    EXPECT_TRUE(r.inputs[size_t(i)].pwm.empty());
  }
  EXPECT_EQ(r.w(), 11) << "the servos drive inputs; the sensors are the 11 optical channels";
}

TEST(RigServos, TwoServosWithOneIdOnABusNameTheFirst) {
  expect_error(edit("address = 2", "address = 1"), line("address = 2"), "[[device]] #2 address",
               "usart1 id 1 is already used by [[device]] #1 (line " + std::to_string(line("address = 1") - 0) + ")");
}

TEST(RigServos, AnUnknownServoModelOrProtocolIsRefusedWithTheKnownOnes) {
  expect_error(edit("chip = \"rx-64\"", "chip = \"rx-28\""), line("chip = \"rx-64\""), "[[device]] #1 chip",
               "'rx-28' is not one of: lis3mdl, lsm303dlhc_mag, dps310, max1111, rx-64, mx-28, ax-12a, xl430-w250, "
               "xm430-w350");
  // A sensor chip on the servo bus, a servo on an I2C bus.
  expect_error(edit("chip = \"rx-64\"", "chip = \"lis3mdl\""), line("chip = \"rx-64\""), "[[device]] #1 chip",
               "usart1 is a serial (servo) bus, and chip lis3mdl is no servo");
  expect_error(edit("bus = \"usart1\"", "bus = \"i2c1\""), line("bus = \"usart1\""), "[[device]] #1 bus",
               "chip rx-64 is a servo on a serial bus, and i2c1 is an I2C bus");
  // An id past protocol 1.0's.
  expect_error(edit("address = 1", "address = 254"), line("address = 1"), "[[device]] #1 address",
               "must be in [0, 253] (a Dynamixel 1.0 id), not 254");
}

TEST(RigServos, ABusPinTheBoardLacksListsItsBuses) {
  expect_error(edit("bus = \"usart1\"", "bus = \"usart3\""), line("bus = \"usart1\""), "[[device]] #1 bus",
               "unknown bus 'usart3' on board stm32f4 (buses: i2c1, spi1, spi2, usart1, usart6)");
  // The bus takes its pin: PB6 is a PWM pin too, and usart1's from its first servo on.
  std::string t = edit("servo = \"rx64-1\"\ngoal_per_unit = 195.57\ngoal_at_neutral = 512\n", "pwm = \"PB6\"\n");
  t = edit("rate_hz = 25\n\n[[device]]\nname = \"rx64-2\"", "rate_hz = 25\n\n[[device]]\nname = \"rx64-2\"", 1, t);
  expect_error(t, line_of(t, "bus = \"usart1\""), "[[device]] #1 bus", "PB6 is already used by [[input]] #1");
}

TEST(RigServos, ABaudTheUsartCannotMakeIsRefused) {
  // 4 Mbit/s: APB2 at 90 MHz (an F446) divides to 3.913 Mbit/s, 2.2 % off.
  std::string t = edit("chip = \"rx-64\"", "chip = \"xm430-w350\"");
  t = edit("chip = \"rx-64\"", "chip = \"xm430-w350\"", 1, t);
  t = edit("goal_per_unit = 195.57\ngoal_at_neutral = 512", "goal_per_unit = 651.9\ngoal_at_neutral = 2048", 1, t);
  t = edit("goal_per_unit = 195.57\ngoal_at_neutral = 512", "goal_per_unit = 651.9\ngoal_at_neutral = 2048", 1, t);
  EXPECT_NO_THROW(parse_rig(t, "my.toml"));
  expect_error(edit("baud = 1000000", "baud = 4000000", 1, t), line_of(t, "baud = 1000000"), "[[device]] #1 baud",
               "bus usart1 cannot make 4000000 baud within 2 % on board stm32f4");
  // Above the servo's fastest; two bauds on one bus.
  expect_error(edit("baud = 1000000", "baud = 2000000"), line("baud = 1000000"), "[[device]] #1 baud",
               "2000000 baud is above chip rx-64's fastest, 1000000");
  expect_error(edit("baud = 1000000", "baud = 57600", 2), line("baud = 1000000", 2), "[[device]] #2 baud",
               "57600 baud, and device rx64-1 (line " + std::to_string(line("name = \"rx64-1\"") - 1) +
                   ") runs bus usart1 at 1000000: one bus, one baud");
}

TEST(RigServos, AnInputNamesOneServoOfTheFileInRange) {
  expect_error(edit("servo = \"rx64-2\"", "servo = \"rx64-3\""), line("servo = \"rx64-2\""), "[[input]] #2 servo",
               "no servo [[device]] is named 'rx64-3' (servos: rx64-1, rx64-2)");
  expect_error(edit("servo = \"rx64-2\"", "servo = \"rx64-1\""), line("servo = \"rx64-2\""), "[[input]] #2 servo",
               "servo rx64-1 already drives input servo1");
  expect_error(edit("neutral = 0.0\nservo", "neutral = 0.0\npwm = \"PC7\"\nservo"), line("servo = \"rx64-1\"") + 1,
               "[[input]] #1 servo", "a servo or a PWM pin drives it, not both");
  // +-1.2 rad at 500 steps a rad leaves 0..1023.
  expect_error(edit("goal_per_unit = 195.57", "goal_per_unit = 500"), line("goal_per_unit = 195.57"),
               "[[input]] #1 goal_per_unit", "puts min = -1.2 at goal -88");
  expect_error(edit("goal_per_unit = 195.57", "goal_per_unit = 0"), line("goal_per_unit = 195.57"),
               "[[input]] #1 goal_per_unit", "must be a finite number other than 0");
  const std::string no_servo = edit("servo = \"rx64-1\"\n", "");
  expect_error(no_servo, line_of(no_servo, "goal_per_unit = 195.57"), "[[input]] #1 goal_per_unit",
               "only with servo = \"DEVICE\"");
  // A servo nothing drives and nobody reads.
  const std::string undriven = edit("servo = \"rx64-2\"\ngoal_per_unit = 195.57\ngoal_at_neutral = 512\n", "");
  expect_error(undriven, line_of(undriven, "name = \"rx64-2\""), "[[device]] #2 name",
               "no [[sensor]] reads device 'rx64-2': give a sensor source = \"device\" with device = \"rx64-2\", or an "
               "[[input]] servo = \"rx64-2\", or remove the device");
}

TEST(RigServos, OnFaultIsHoldOrRelease) {
  const Rig r = parse_rig(edit("rate_hz = 25\n", "rate_hz = 25\non_fault = \"release\"\n", 2), "my.toml");
  EXPECT_FALSE(r.devices[0].release_on_fault);
  EXPECT_TRUE(r.devices[1].release_on_fault);
  expect_error(edit("rate_hz = 25\n", "rate_hz = 25\non_fault = \"stop\"\n"), line("rate_hz = 25") + 1,
               "[[device]] #1 on_fault", "'stop' is not one of: hold, release");
}

TEST(RigServos, AnMps2An386RigHasNoServoBus) {
  std::string t = edit("board = \"stm32f4\"", "board = \"mps2-an386\"");
  expect_error(t, line("bus = \"usart1\""), "[[device]] #1 bus", "unknown bus 'usart1' on board mps2-an386");
}

}  // namespace
}  // namespace nlsoft::host
