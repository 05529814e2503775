// Text shortened to a width by rule (app/tui/fit_text.hpp): by words, never
// inside a number; a path by its middle; a line of fields by its least
// useful fields first.
#include <gtest/gtest.h>

#include "app/tui/fit_text.hpp"

namespace nlsoft::console::tui {
namespace {

const std::string kMore = "\u2026";

TEST(FitText, ASentenceLosesWholeWordsAndItsPunctuationBeforeTheEllipsis) {
  const std::string s = "run 1 stopped: 1481 samples, nrmse 0.0123, lost 0";
  EXPECT_EQ(elide_words(s, 100, kMore), s);
  EXPECT_EQ(elide_words(s, 40, kMore), "run 1 stopped: 1481 samples, nrmse\u2026");
  // One column short of the number: the number goes whole.
  EXPECT_EQ(elide_words(s, 41, kMore), "run 1 stopped: 1481 samples, nrmse\u2026");
  EXPECT_EQ(elide_words(s, 42, kMore), "run 1 stopped: 1481 samples, nrmse 0.0123\u2026");
  for (size_t w = 8; w <= s.size(); ++w) {
    const std::string shown = elide_words(s, w, kMore);
    EXPECT_LE(text_columns(shown), w) << shown;
    if (shown == s) continue;
    const std::string head = shown.substr(0, shown.size() - kMore.size());
    ASSERT_EQ(s.compare(0, head.size(), head), 0) << shown;
    auto in_number = [](char c) { return std::string("0123456789.").find(c) != std::string::npos; };
    EXPECT_FALSE(in_number(head.back()) && in_number(s[head.size()])) << "cut inside a number: " << shown;
  }
}

TEST(FitText, AWordWithoutBlanksIsCutBetweenItsItems) {
  EXPECT_EQ(elide_words(R"(reference {"a":4.0,"b":4.0,"kind":"diagonal"})", 30, kMore),
            "reference {\"a\":4.0,\"b\":4.0\u2026");
  EXPECT_EQ(elide_words("Q = 1e+06,2e+06,1e+06", 18, kMore), "Q = 1e+06,2e+06\u2026");
}

TEST(FitText, APathLosesItsMiddleFoldersAndKeepsItsFileName) {
  const std::string p = "/tmp/nlsoft-a-long-folder/another-folder/runs.db";
  EXPECT_EQ(elide_path(p, 100, kMore), p);
  EXPECT_EQ(elide_path(p, 20, kMore), "/tmp/nlsoft\u2026/runs.db");
  EXPECT_EQ(text_columns(elide_path(p, 20, kMore)), 20u);
  // In a sentence, a path cut off keeps its file name.
  EXPECT_EQ(elide_words("run 1 started, recording to " + p, 50, kMore),
            "run 1 started, recording to /tmp/nlsoft-a\u2026/runs.db");
}

TEST(FitText, FieldsGoLeastUsefulFirst) {
  const std::vector<Field> f = {{"link up /dev/pts/3", 9}, {"2.6k fr/s 92kB/s", 1}, {"lost 0", 6}, {"loop 130.0 Hz", 7}};
  EXPECT_EQ(fit_fields(f, " | ", 100, kMore), "link up /dev/pts/3 | 2.6k fr/s 92kB/s | lost 0 | loop 130.0 Hz");
  EXPECT_EQ(fit_fields(f, " | ", 45, kMore), "link up /dev/pts/3 | lost 0 | loop 130.0 Hz");
  EXPECT_EQ(fit_fields(f, " | ", 36, kMore), "link up /dev/pts/3 | loop 130.0 Hz");
}

TEST(FitText, WrappedLinesKeepWordsAndSplitALongPathAtItsSlashes) {
  EXPECT_EQ(wrap_words("nrmse 0.0123, lost 0", 12), (std::vector<std::string>{"nrmse", "0.0123, lost", "0"}));
  EXPECT_EQ(wrap_words("/tmp/a-folder/runs.db", 10), (std::vector<std::string>{"/tmp/a-", "folder/", "runs.db"}));
}

// A panel's key hints: whole ones in order, then an ellipsis where some do
// not fit ("A r" and "R re" were hints cut inside).
TEST(FitText, KeyHintsAreDroppedWholeAndTheLineEndsInAnEllipsis) {
  const std::vector<std::string> hints = {"Enter edit", "u undo", "S/L save/load", "R reread", "A reapply"};
  const std::string all = "Enter edit  u undo  S/L save/load  R reread  A reapply";
  EXPECT_EQ(fit_hints(hints, 100, kMore), all);
  EXPECT_EQ(fit_hints(hints, all.size(), kMore), all);
  EXPECT_EQ(fit_hints(hints, all.size() - 1, kMore), "Enter edit  u undo  S/L save/load  R reread \u2026");
  EXPECT_EQ(fit_hints(hints, 46, kMore), "Enter edit  u undo  S/L save/load  R reread \u2026");
  EXPECT_EQ(fit_hints(hints, 45, kMore), "Enter edit  u undo  S/L save/load  R reread \u2026");
  EXPECT_EQ(fit_hints(hints, 44, kMore), "Enter edit  u undo  S/L save/load \u2026");
  EXPECT_EQ(fit_hints(hints, 5, kMore), kMore);
  for (size_t w = 1; w < all.size(); ++w) {
    const std::string shown = fit_hints(hints, w, kMore);
    EXPECT_LE(text_columns(shown), w) << shown;
    ASSERT_GE(shown.size(), kMore.size()) << w;
    EXPECT_EQ(shown.substr(shown.size() - kMore.size()), kMore) << shown;
    // Every hint shown is whole.
    const std::string head = shown.substr(0, shown.size() - kMore.size());
    EXPECT_EQ(all.compare(0, head.size(), head), 0) << shown;
    if (!head.empty()) {
      EXPECT_TRUE(all[head.size() - 1] == ' ' && all[head.size()] == ' ') << "cut inside a hint: " << shown;
    }
  }
}

// Lines for a box of a few rows: those left out leave an ellipsis on the
// last one kept (the Q description stopped at "1/y^2, 3").
TEST(FitText, LinesCutToTheirRoomEndInAnEllipsis) {
  const std::vector<std::string> lines = {"range [0, 1e+12] 1/y^2, 3", "values (one sets all)"};
  EXPECT_EQ(cut_lines(lines, 2, 30, kMore), lines);
  const auto one = cut_lines(lines, 1, 30, kMore);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], "range [0, 1e+12] 1/y^2, 3\u2026");
  EXPECT_TRUE(cut_lines(lines, 0, 30, kMore).empty());
}

}  // namespace
}  // namespace nlsoft::console::tui
