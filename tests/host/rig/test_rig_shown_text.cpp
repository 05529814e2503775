// What a rig file says that a terminal would obey rather than show, and
// ranges whose width a float cannot hold: refused at their line.
#include <gtest/gtest.h>

#include <string>

#include "host/rig/rig.hpp"
#include "rig_text.hpp"

namespace nlsoft::host {
namespace {

const char* kBase = R"(name = "probe"
description = "a probe"
rate_hz = 100.0
nd = 2
dd = 2

[[input]]
name = "u1"
unit = "V"
min = 0.0
max = 1.0
neutral = 0.5

[[output]]
name = "x"
unit = "mm"
min = -10.0
max = 10.0

[controller]
Q = [1.0]
Lambda = [1.0]
s = 1e-20
b = 1e-5
r = 400.0
N = 3
Nc = 1
eps = 0.01
)";

using rig_text::expect_error;
using rig_text::line_of;

std::string edit(const std::string& from, const std::string& to, int nth = 1) {
  return rig_text::replaced(kBase, from, to, nth);
}

// U+009B is the one-byte CSI (ESC [ in C1 form); U+202E shows what follows
// it right to left. Both were accepted where 0x1b was refused.
TEST(RigShownText, C1AndBidirectionalControlsAreRefusedLikeEscape) {
  const int unit_line = line_of(kBase, "unit = \"V\"");
  expect_error(edit("unit = \"V\"", "unit = \"V\\u009b2J\""), unit_line, "[[input]] #1 unit",
               "holds the control character U+009B: one line of text");
  expect_error(edit("unit = \"V\"", "unit = \"V\\u0085\""), unit_line, "[[input]] #1 unit",
               "holds the control character U+0085");
  const int desc_line = line_of(kBase, "description = ");
  for (const char* bidi : {"\\u202e", "\\u202a", "\\u2066", "\\u2069", "\\u200f", "\\u061c"})
    expect_error(edit("description = \"a probe\"", std::string("description = \"a ") + bidi + "probe\""), desc_line,
                 "description", "holds a bidirectional control");
  const int out_unit = line_of(kBase, "unit = \"mm\"");
  expect_error(edit("unit = \"mm\"", "unit = \"mm\\u202e\""), out_unit, "[[output]] #1 unit",
               "holds a bidirectional control");
  // Letters beyond ASCII stay text: a unit in µm, a description in Greek or
  // Arabic (U+0600.. save U+061C), a dash U+2014 beside the controls' block.
  for (const char* good : {"\\u00b5m", "\\u03a9", "\\u0627", "a \\u2014 b", "\\u00a0"})
    EXPECT_NO_THROW(parse_rig(edit("unit = \"V\"", std::string("unit = \"") + good + "\""), "my.toml")) << good;
}

// 1.7e308 - -1.7e308 is inf: the rig used to load with "span inf", and
// every step, amplitude and normalisation made from it was infinite.
TEST(RigShownText, ARangeWiderThanAFloatIsRefusedWithTheSpan) {
  const std::string out = edit("min = -10.0", "min = -1.7e308");
  const std::string wide = rig_text::replaced(out, "max = 10.0", "max = 1.7e308");
  expect_error(wide, line_of(wide, "min = -1.7e308"), "[[output]] #1 min", "must be a float");
  // Each bound a float, the width not: the span is named.
  const std::string span = rig_text::replaced(rig_text::replaced(kBase, "min = -10.0", "min = -3e38"), "max = 10.0",
                                              "max = 3e38");
  expect_error(span, line_of(span, "max = 3e38"), "[[output]] #1 max", "makes the span max - min = 6e+38");
  const std::string in = rig_text::replaced(rig_text::replaced(kBase, "min = 0.0", "min = -3e38"), "max = 1.0",
                                            "max = 3e38");
  expect_error(rig_text::replaced(in, "neutral = 0.5", "neutral = 0.0"), line_of(in, "max = 3e38"),
               "[[input]] #1 max", "makes the span max - min = 6e+38");
  const std::string given = rig_text::replaced(kBase, "max = 10.0", "max = 10.0\nspan = 1e300");
  expect_error(given, line_of(given, "span = 1e300"), "[[output]] #1 span", "must be a float");
  // The widest a float holds loads.
  EXPECT_NO_THROW(parse_rig(rig_text::replaced(rig_text::replaced(kBase, "min = -10.0", "min = -1e38"), "max = 10.0",
                                               "max = 1e38"),
                            "my.toml"));
}

}  // namespace
}  // namespace nlsoft::host
