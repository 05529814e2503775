// train's note on inputs a run held at one value or switched between two.
#include <gtest/gtest.h>

#include "app/model/input_levels.hpp"

namespace nlsoft::model {
namespace {

// A run of m inputs whose input i takes values from its own list in turn.
Series run_of(const std::vector<std::vector<double>>& levels, long rows) {
  Series s;
  s.resize(rows, int(levels.size()), 1, 0);
  for (long r = 0; r < rows; ++r) {
    s.time(r) = 0.01 * double(r);
    for (size_t i = 0; i < levels.size(); ++i) s.u(r, long(i)) = levels[i][size_t(r) % levels[i].size()];
    s.y(r, 0) = 0.0;
  }
  return s;
}

TEST(InputLevels, CountsOneTwoOrMoreLevelsPerInputOverEveryRun) {
  const Series a = run_of({{0.5}, {0.1, 0.9}, {0.1, 0.9}, {0.2, 0.4, 0.6}}, 50);
  EXPECT_EQ(input_level_counts({a}), (std::vector<int>{1, 2, 2, 3}));
  // A second run at another level makes u0 two-level and u1 three-level.
  const Series b = run_of({{0.7}, {0.5}, {0.9, 0.1}, {0.2}}, 20);
  EXPECT_EQ(input_level_counts({a, b}), (std::vector<int>{2, 3, 2, 3}));
  EXPECT_EQ(input_level_counts({}), (std::vector<int>{}));
}

TEST(InputLevels, NamesTheHeldAndTheTwoLevelInputs) {
  const std::vector<std::string> notes =
      input_level_notes({run_of({{0.5}, {0.1, 0.9}, {0.3, 0.6, 0.9}, {0.0, 1.0}}, 30)});
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_NE(notes[0].find("u0 held one value through every run"), std::string::npos) << notes[0];
  EXPECT_NE(notes[1].find("u1 and u3 took two levels only"), std::string::npos) << notes[1];
  EXPECT_NE(notes[1].find("aprbs"), std::string::npos) << notes[1];
  EXPECT_EQ(notes[0].find("u2"), std::string::npos);
  EXPECT_EQ(notes[1].find("u2"), std::string::npos);
}

TEST(InputLevels, SaysNothingWhenEveryInputTookThreeLevels) {
  EXPECT_TRUE(input_level_notes({run_of({{0.1, 0.2, 0.3}, {0.9, 0.5, 0.1, 0.4}}, 12)}).empty());
}

}  // namespace
}  // namespace nlsoft::model
