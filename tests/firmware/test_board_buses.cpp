// The boards' buses and chip selects as the console sees them
// (host/rig/board_pins) against the tables the ports drive: the same
// names, kinds and pins, no pin given to two jobs except where the board
// table says so (SPI1 on ADC1_IN6/IN7's pins), and mps2-an386 a board a
// rig file may name for its buses alone.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "firmware/ports/mps2-an386/buses.hpp"
#include "host/rig/board_pins.hpp"
#include "shared/board_stm32f4.hpp"

using namespace nlsoft;


TEST(BoardBuses, An386BusesAreThePortsAndARigFileNamesThemAlone) {
  const host::BoardPins* b = host::find_board("mps2-an386");
  ASSERT_NE(b, nullptr);
  ASSERT_EQ(b->buses.size(), std::size(fw::an386::kI2cBuses) + std::size(fw::an386::kSpiBuses));
  size_t i = 0;
  for (const auto& c : fw::an386::kI2cBuses) {
    EXPECT_EQ(b->buses[i].name, c.name);
    EXPECT_EQ(b->buses[i].kind, BusKind::I2c);
    ++i;
  }
  for (const auto& c : fw::an386::kSpiBuses) {
    EXPECT_EQ(b->buses[i].name, c.name);
    EXPECT_EQ(b->buses[i].kind, BusKind::Spi);
    EXPECT_TRUE(b->buses[i].own_chip_select) << c.name;
    ++i;
  }
  EXPECT_TRUE(b->pwm.empty());
  EXPECT_TRUE(b->chip_selects.empty());
  EXPECT_TRUE(b->adc.empty());
  // The board table's order (host/rig/board_table.cpp).
  EXPECT_EQ(host::board_names(), (std::vector<std::string>{"mps2-an386", "stm32f4", "mps2-an500", "mps2-an385"}));
}

TEST(BoardBuses, Stm32f4BusesAndChipSelectsTakeNoPinTwice) {
  const host::BoardPins* b = host::find_board("stm32f4");
  ASSERT_NE(b, nullptr);
  ASSERT_EQ(b->buses.size(), 5u);
  EXPECT_EQ(b->buses[0].name, "i2c1");
  EXPECT_EQ(b->buses[0].kind, BusKind::I2c);
  EXPECT_EQ(b->buses[0].pins, (std::vector<std::string>{"PB8", "PB9"}));
  EXPECT_EQ(b->buses[1].name, "spi1");
  EXPECT_EQ(b->buses[1].pins, (std::vector<std::string>{"PA5", "PA6", "PA7"}));
  EXPECT_EQ(b->buses[2].name, "spi2");
  EXPECT_EQ(b->buses[2].kind, BusKind::Spi);
  EXPECT_EQ(b->buses[2].pins, (std::vector<std::string>{"PB13", "PB14", "PB15"}));
  // The servo buses, each on its USART's TX pin alone (single wire).
  EXPECT_EQ(b->buses[3].name, "usart1");
  EXPECT_EQ(b->buses[3].kind, BusKind::Serial);
  EXPECT_EQ(b->buses[3].pins, (std::vector<std::string>{"PB6"}));
  EXPECT_EQ(b->buses[4].name, "usart6");
  EXPECT_EQ(b->buses[4].pins, (std::vector<std::string>{"PC6"}));
  ASSERT_NE(b->buses[3].makes_baud, nullptr);
  EXPECT_TRUE(b->buses[3].makes_baud(1000000u));
  EXPECT_TRUE(b->buses[3].makes_baud(57600u));
  EXPECT_FALSE(b->buses[3].makes_baud(4000000u)) << "3.913 Mbit/s on the F446's 90 MHz APB2";
  EXPECT_FALSE(b->buses[3].makes_baud(6000000u)) << "a divider under 16";
  EXPECT_EQ(b->chip_selects.size(), size_t(fw::stm32f4::kChipSelectCount));
  ASSERT_EQ(b->adc_pins.size(), b->adc.size());

  // Every job a pin has on the board; the link (USART2), SWD and the button are taken too.
  std::multimap<std::string, std::string> jobs = {
      {"PA2", "USART2"}, {"PA3", "USART2"}, {"PA13", "SWD"}, {"PA14", "SWD"}, {"PC13", "button"}};
  for (const std::string& p : b->pwm) jobs.insert({p, "PWM"});
  for (size_t i = 0; i < b->adc.size(); ++i) jobs.insert({b->adc_pins[i], "ADC1_IN" + std::to_string(b->adc[i])});
  for (const auto& bus : b->buses)
    for (const std::string& p : bus.pins) jobs.insert({p, bus.name});
  for (const std::string& p : b->chip_selects) jobs.insert({p, "chip select"});
  for (auto it = jobs.begin(); it != jobs.end();) {
    const auto [first, last] = jobs.equal_range(it->first);
    std::vector<std::string> js;
    for (auto j = first; j != last; ++j) js.push_back(j->second);
    if (js.size() > 1) {
      // The sharing the table declares: SPI1's MISO/MOSI are ADC1_IN6/IN7's
      // pins, and the servo buses' TX pins PWM pins (a rig uses one or the other).
      auto pair_of = [&](const char* a, const char* b_prefix) {
        return js.size() == 2 && ((js[0] == a && js[1].rfind(b_prefix, 0) == 0) ||
                                  (js[1] == a && js[0].rfind(b_prefix, 0) == 0));
      };
      const bool declared = pair_of("spi1", "ADC1_IN") || pair_of("usart1", "PWM") || pair_of("usart6", "PWM");
      EXPECT_TRUE(declared) << it->first << " has " << js.size() << " jobs: " << js[0] << ", " << js[1];
    }
    it = last;
  }
  EXPECT_EQ(jobs.count("PA6"), 2u);
  EXPECT_EQ(jobs.count("PA7"), 2u);
}
