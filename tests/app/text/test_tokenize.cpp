// A line's words as typed in scripts, the TUI's ':' line and tune's words.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "app/text/tokenize.hpp"

namespace nlsoft::console::text {
namespace {

using Words = std::vector<std::string>;

TEST(Tokenize, BlanksSplitAndQuotesGroup) {
  EXPECT_EQ(tokenize("set Q 1e6  2e6\t1e6"), (Words{"set", "Q", "1e6", "2e6", "1e6"}));
  EXPECT_EQ(tokenize("run 10s label=\"a b\""), (Words{"run", "10s", "label=a b"}));
  EXPECT_EQ(tokenize("echo \"say \\\"hi\\\"\""), (Words{"echo", "say \"hi\""}));
  EXPECT_EQ(tokenize("\"\""), (Words{""})) << "an empty quoted word is a word";
  EXPECT_EQ(tokenize("   "), Words{});
}

TEST(Tokenize, AHashStartingAWordEndsTheLine) {
  EXPECT_EQ(tokenize("run 5s # the baseline"), (Words{"run", "5s"}));
  EXPECT_EQ(tokenize("# all comment"), Words{});
  EXPECT_EQ(tokenize("label=a#b"), (Words{"label=a#b"})) << "inside a word it is a character";
}

TEST(Tokenize, AnUnterminatedQuoteIsRefused) {
  EXPECT_THROW(tokenize("echo \"open"), std::invalid_argument);
}

}  // namespace
}  // namespace nlsoft::console::text
