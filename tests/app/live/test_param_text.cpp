// Parameters that explain themselves: option names as values, one value for
// every element, and the words the panel shows for the selected row.
#include <gtest/gtest.h>

#include "host/files/cli_error.hpp"
#include "app/live/param_text.hpp"
#include "app/tui/plot_view.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

ParamInfo param(const char* name, protocol::ParamType type, uint8_t size, float lo = 0, float hi = 1e12f,
                const char* unit = "") {
  ParamInfo p;
  p.name = name;
  p.type = type;
  p.size = size;
  p.min = lo;
  p.max = hi;
  p.unit = unit;
  return p;
}

std::string thrown_message(const std::function<void()>& f) {
  try {
    f();
  } catch (const CliError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamText, OptionsByNameAndNumbersStillAccepted) {
  const ParamInfo mode = param("mode", protocol::ParamType::Enum, 1, 0, 1);
  EXPECT_EQ(parse_param_values(mode, expand_param_tokens(mode, {"fd"})), std::vector<double>{1});
  EXPECT_EQ(parse_param_values(mode, expand_param_tokens(mode, {"EXACT"})), std::vector<double>{0});
  EXPECT_EQ(parse_param_values(mode, expand_param_tokens(mode, {"1"})), std::vector<double>{1});
  const ParamInfo fb = param("feedback", protocol::ParamType::Enum, 1, 0, 1);
  EXPECT_EQ(parse_param_values(fb, expand_param_tokens(fb, {"measured"})), std::vector<double>{1});
  const ParamInfo safe = param("safe_state", protocol::ParamType::Enum, 1, 0, 1);
  EXPECT_EQ(parse_param_values(safe, expand_param_tokens(safe, {"hold"})), std::vector<double>{0});
  EXPECT_EQ(format_param_named(safe, {1}), "1 (neutral)");
  EXPECT_EQ(format_param_named(mode, {0}), "0 (exact)");
  EXPECT_EQ(thrown_message([&] { expand_param_tokens(mode, {"newton"}); }),
            "mode: 'newton' is not an option; use exact (0), fd (1)");
}

TEST(ParamText, OneValueSetsEveryElementAndOtherCountsAreStillRefused) {
  const ParamInfo lambda = param("Lambda", protocol::ParamType::F32, 6, 0, 1e12f, "1/u^2");
  EXPECT_EQ(parse_param_values(lambda, expand_param_tokens(lambda, {"0.5"})), std::vector<double>(6, 0.5));
  EXPECT_EQ(parse_param_values(lambda, expand_param_tokens(lambda, {"1,2,3,4,5,6"})),
            (std::vector<double>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(thrown_message([&] { parse_param_values(lambda, expand_param_tokens(lambda, {"1", "2"})); }),
            "Lambda takes 6 values, got 2");
  // Numbers are not option names for a parameter without options.
  EXPECT_EQ(thrown_message([&] { parse_param_values(lambda, expand_param_tokens(lambda, {"fd"})); }),
            "Lambda: 'fd' is not a number");
}

TEST(ParamText, DescriptionRangeAndUnitForThePanel) {
  EXPECT_NE(param_description("Lambda").find("input changes"), std::string::npos);
  EXPECT_NE(param_description("safe_state").find("watchdog"), std::string::npos);
  EXPECT_EQ(param_description("not_a_parameter"), "");
  EXPECT_EQ(param_range_text(param("Lambda", protocol::ParamType::F32, 6, 0, 1e12f, "1/u^2")),
            "range [0, 1e+12] 1/u^2, 6 values (one sets all)");
  EXPECT_EQ(param_range_text(param("N", protocol::ParamType::U8, 1, 1, 255, "steps")),
            "range [1, 255] steps, whole numbers");
  ParamInfo capped = param("N", protocol::ParamType::U8, 1, 1, 12, "steps");
  capped.capacity = "max_n";
  EXPECT_EQ(param_range_text(capped), "range [1, 12] steps (this build's capacity, max_n), whole numbers");
  EXPECT_EQ(param_range_text(param("mode", protocol::ParamType::Enum, 1, 0, 1)), "options exact (0), fd (1)");
}

TEST(PlotView, TimeTicksAreRoundAndInsideTheWindow) {
  EXPECT_EQ(tui::time_ticks(0, 10, 5), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(tui::time_ticks(12.3, 14.9, 3), (std::vector<double>{13, 14}));
  const auto t = tui::time_ticks(-7.5, 2.5, 4);
  EXPECT_EQ(t, (std::vector<double>{-5, 0}));
  EXPECT_TRUE(tui::time_ticks(3, 3, 4).empty());
}

// A view of steps 1000..2000 on 101 columns: 10 steps a column.
TEST(PlotView, TheTimeCursorStartsMidViewMovesByColumnsAndStaysInside) {
  const int64_t mid = tui::move_time_cursor(-1, 2000, 1000, 101, 1);
  EXPECT_EQ(mid, 1500) << "the first key puts the cursor mid-view";
  EXPECT_EQ(tui::move_time_cursor(mid, 2000, 1000, 101, 1), 1510);
  EXPECT_EQ(tui::move_time_cursor(mid, 2000, 1000, 101, -3), 1470);
  EXPECT_EQ(tui::move_time_cursor(1995, 2000, 1000, 101, 1), 2000) << "not past the right edge";
  EXPECT_EQ(tui::move_time_cursor(1005, 2000, 1000, 101, -1), 1000) << "not past the left edge";
  EXPECT_EQ(tui::move_time_cursor(500, 2000, 1000, 101, 1), 1500) << "a cursor the view left restarts mid-view";
  EXPECT_EQ(tui::move_time_cursor(150, 200, 1000, 101, -100), 0) << "a view longer than the run stops at step 0";
  EXPECT_EQ(tui::move_time_cursor(-1, 300, 1000, 101, 1), 150) << "mid-way through what the view shows";
  EXPECT_EQ(tui::move_time_cursor(1500, 1520, 50, 101, 1), 1501) << "zoomed in: one step a key at least";
}

TEST(PlotView, SignalNamesRoundTripAndTheKeyCyclesThroughAll) {
  tui::PlotSignal s = tui::PlotSignal::Y;
  std::vector<std::string> seen;
  for (int i = 0; i < 6; ++i) {
    seen.push_back(tui::plot_signal_name(s));
    tui::PlotSignal back;
    ASSERT_TRUE(tui::plot_signal_from_name(seen.back(), &back));
    EXPECT_EQ(back, s);
    s = tui::next_plot_signal(s);
  }
  EXPECT_EQ(seen, (std::vector<std::string>{"y", "u", "cost", "iter", "compute", "ident"}));
  EXPECT_EQ(s, tui::PlotSignal::Y);
  tui::PlotSignal x;
  EXPECT_FALSE(tui::plot_signal_from_name("J", &x));
}

}  // namespace
}  // namespace nlsoft::console
