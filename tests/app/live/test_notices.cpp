// What the console says before anyone listens waits for the first listener,
// up to a bound; a listener detached hears nothing more.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/live/notices.hpp"

namespace nlsoft::console {
namespace {

TEST(Notices, WhatIsSaidBeforeAListenerReachesTheFirstOneUpToThirtyTwo) {
  Notices n;
  for (int i = 0; i < 40; ++i) n.say("line " + std::to_string(i));
  std::vector<std::string> heard;
  n.listen([&](const std::string& s) { heard.push_back(s); });
  ASSERT_EQ(heard.size(), 32u);
  EXPECT_EQ(heard.front(), "line 0");
  EXPECT_EQ(heard.back(), "line 31");
  n.say("now");
  ASSERT_EQ(heard.size(), 33u);
  EXPECT_EQ(heard.back(), "now");
}

TEST(Notices, ADetachedListenerHearsNothingAndTheNextOneHearsTheRest) {
  Notices n;
  std::vector<std::string> first, second;
  n.listen([&](const std::string& s) { first.push_back(s); });
  n.say("a");
  n.listen({});
  n.say("b");
  n.listen([&](const std::string& s) { second.push_back(s); });
  EXPECT_EQ(first, std::vector<std::string>{"a"});
  EXPECT_EQ(second, std::vector<std::string>{"b"});
}

}  // namespace
}  // namespace nlsoft::console
