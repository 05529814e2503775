// Durations as typed in scripts, tune's words, ident and runs list --since.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "app/text/duration.hpp"

namespace nlsoft::console::text {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_duration(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Duration, UnitsScaleToSeconds) {
  EXPECT_DOUBLE_EQ(parse_duration("1.5s"), 1.5);
  EXPECT_DOUBLE_EQ(parse_duration("2sec"), 2.0);
  EXPECT_DOUBLE_EQ(parse_duration("20ms"), 0.02);
  EXPECT_DOUBLE_EQ(parse_duration("2min"), 120.0);
  EXPECT_DOUBLE_EQ(parse_duration("2m"), 120.0);
  EXPECT_DOUBLE_EQ(parse_duration("1h"), 3600.0);
}

TEST(Duration, MistakesAreSaidInWords) {
  EXPECT_THROW(parse_duration("s"), std::invalid_argument);
  EXPECT_EQ(error_of("ten"), "'ten' is not a duration (e.g. 5s, 250ms, 2min)");
  EXPECT_EQ(error_of("5"), "'5' needs a unit: 5s, 5ms or 5min");
  EXPECT_EQ(error_of("5d"), "'5d': unknown unit 'd' (use ms, s, min or h)");
  EXPECT_EQ(error_of("-1s"), "'-1s': a duration must be > 0");
  EXPECT_EQ(error_of("0s"), "'0s': a duration must be > 0");
  EXPECT_EQ(error_of("721h"), "'721h': a duration is at most 30 days (720h)");
  EXPECT_DOUBLE_EQ(parse_duration("720h"), 720 * 3600.0);
}

}  // namespace
}  // namespace nlsoft::console::text
