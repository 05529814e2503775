// What `tune` checks before it connects: the objective expression, the
// ranges, the budget and the options; the input metrics the objective can
// read; the convergence plot's script.
#include <gtest/gtest.h>

#include <cmath>

#include "app/record/run_metrics.hpp"
#include "app/record/tune_log.hpp"
#include "app/script/script_parser.hpp"
#include "app/tune/motion_check.hpp"
#include "app/tune/objective.hpp"
#include "app/tune/search_space.hpp"
#include "app/tune/tune_options.hpp"

namespace nlsoft::console {
namespace {

RunMetrics metrics(double nrmse, double u_effort) {
  RunMetrics m;
  m.has_true = true;
  m.truth.nrmse = nrmse;
  m.u_effort = u_effort;
  return m;
}

std::string objective_error(const std::string& objective) {
  try {
    Objective o(objective);
  } catch (const ObjectiveError& e) {
    return e.what();
  }
  return "";
}

TEST(TuneObjective, ArithmeticOverMetricsWithPrecedenceAndParentheses) {
  EXPECT_DOUBLE_EQ(Objective("nrmse + 0.1*u_effort")(metrics(0.05, 0.2)), 0.07);
  EXPECT_DOUBLE_EQ(Objective("(nrmse + 1) * 2 - -u_effort / 4")(metrics(0.5, 2)), 3.5);
  EXPECT_EQ(Objective("nrmse + 0.1*u_effort + nrmse").metrics(), (std::vector<std::string>{"nrmse", "u_effort"}));
  EXPECT_TRUE(std::isnan(Objective("rmse1")(metrics(0, 0)))) << "a run without axis 1 cannot be scored on it";
}

TEST(TuneObjective, AMissingMetricMakesTheScoreUndefinedNotZero) {
  RunMetrics m = metrics(0.05, 0);
  m.nrmse_space = std::nan("");
  EXPECT_TRUE(std::isnan(Objective("nrmse + nrmse_space")(m)));
  EXPECT_TRUE(std::isnan(Objective("nrmse / 0 ")(m))) << "an infinite score is no score";
}

TEST(TuneObjective, BadExpressionsSayWhatAndWhere) {
  EXPECT_NE(objective_error("nrmse + * 2").find("column 9"), std::string::npos) << objective_error("nrmse + * 2");
  EXPECT_NE(objective_error("nrmse + effort").find("unknown metric 'effort'"), std::string::npos);
  EXPECT_NE(objective_error("nrmse + effort").find("u_effort"), std::string::npos) << "lists the known metrics";
  EXPECT_NE(objective_error("(nrmse").find("expected ')'"), std::string::npos);
  EXPECT_NE(objective_error("nrmse 2").find("unexpected '2'"), std::string::npos);
  EXPECT_NE(objective_error("  ").find("empty"), std::string::npos);
}

TEST(TuneSpace, RangesParseLinearOrLog) {
  const Dimension d = parse_dimension("Lambda=0.01..100:log");
  EXPECT_EQ(d.name, "Lambda");
  EXPECT_DOUBLE_EQ(d.lo, 0.01);
  EXPECT_DOUBLE_EQ(d.hi, 100);
  EXPECT_TRUE(d.log);
  const Dimension q = parse_dimension("Q*=-1..1");
  EXPECT_EQ(q.name, "Q*");
  EXPECT_FALSE(q.log);
  EXPECT_DOUBLE_EQ(q.lo, -1);
  // :lin is the default written out: valid, and linear.
  const Dimension lin = parse_dimension("Lambda=0.5..2:lin");
  EXPECT_FALSE(lin.log);
  EXPECT_DOUBLE_EQ(lin.hi, 2);
}

// Every place that teaches the range syntax names both scales, so :lin is
// known to be valid before it is tried.
TEST(TuneSpace, TheHelpNamesBothScales) {
  std::string help;
  for (const std::string& line : tune_help()) help += line + "\n";
  EXPECT_NE(help.find("[:log|:lin]"), std::string::npos) << help;
  EXPECT_NE(help.find(":lin (the default)"), std::string::npos) << help;
  try {
    parse_dimension("Lambda=1..10:LOG");
    ADD_FAILURE() << "an unknown scale is refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("':LOG' is not a scale; use :log or :lin"), std::string::npos) << e.what();
  }
}

// A time budget of nothing is refused as such, not as an unreadable budget.
TEST(TuneWords, AZeroTimeBudgetMustBePositive) {
  for (const char* zero : {"0s", "0min", "0 ms"}) {
    TuneOptions o;
    try {
      set_budget(o, zero);
      ADD_FAILURE() << zero << " was taken";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("a time budget must be positive"), std::string::npos) << e.what();
    }
  }
  TuneOptions o;
  try {
    set_budget(o, "0lightyears");
    ADD_FAILURE() << "an unknown unit was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("give runs (40) or wall time"), std::string::npos) << e.what();
  }
}

TEST(TuneSpace, BadRangesAreRefusedInWords) {
  auto error = [](const std::string& s) -> std::string {
    try {
      parse_dimension(s);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error("Lambda").find("expected NAME=LO..HI"), std::string::npos);
  EXPECT_NE(error("Lambda=5..1").find("LO must be below HI"), std::string::npos);
  EXPECT_NE(error("Lambda=0..1:log").find("LO > 0"), std::string::npos);
  EXPECT_NE(error("Lambda=1..x").find("'x' is not a number"), std::string::npos);
  EXPECT_NE(error("Lambda=1..10:ln").find("use :log or :lin"), std::string::npos);
  EXPECT_NE(error("Lambda=1-10").find("LO..HI"), std::string::npos);
}

TEST(TuneWords, TheScriptFormCarriesEveryOption) {
  const TuneOptions o = parse_tune_words({"Lambda=0.01..100:log", "Q1=1e5..1e7:log", "objective=nrmse + 0.1*u_effort",
                                          "budget=12", "budget=2min", "reference=swirl", "settle=500ms", "window=3s",
                                          "seed=7", "method=neldermead", "max_saturated=0.25", "save=best.params", "apply"});
  ASSERT_EQ(o.dims.size(), 2u);
  EXPECT_EQ(o.dims[1].name, "Q1");
  EXPECT_EQ(o.objective, "nrmse + 0.1*u_effort");
  EXPECT_EQ(o.budget_runs, 12);
  EXPECT_DOUBLE_EQ(o.budget_s, 120);
  EXPECT_EQ(o.reference, "swirl");
  EXPECT_DOUBLE_EQ(o.settle_s, 0.5);
  EXPECT_DOUBLE_EQ(o.window_s, 3);
  EXPECT_EQ(o.seed, 7u);
  EXPECT_EQ(o.method, "neldermead");
  EXPECT_DOUBLE_EQ(o.max_saturated, 0.25);
  EXPECT_EQ(o.save, "best.params");
  EXPECT_TRUE(o.apply);
  EXPECT_EQ(parse_tune_words({"Lambda=1..2", "budget=90s"}).budget_runs, 0) << "a time budget alone: as many runs as fit";
  EXPECT_EQ(parse_tune_words({"Lambda=1..2"}).budget_runs, 40);
  TuneOptions spaced;
  EXPECT_TRUE(set_budget(spaced, "25 runs"));
  EXPECT_FALSE(set_budget(spaced, "10 min"));
  EXPECT_EQ(spaced.budget_runs, 25);
  EXPECT_DOUBLE_EQ(spaced.budget_s, 600);
}

TEST(TuneWords, ScriptLinesAreCheckedBeforeAnythingRuns) {
  auto error = [](const std::string& line) -> std::string {
    try {
      parse_command(line, "t.nls", 3);
    } catch (const ScriptError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(parse_command("tune Lambda=0.01..100:log objective=\"nrmse + 0.1*u_effort\"", "t.nls", 1).kind,
            Command::Kind::Tune);
  EXPECT_NE(error("tune").find("t.nls:3: tune: nothing to search"), std::string::npos) << error("tune");
  EXPECT_NE(error("tune Lambda=1..2 objective=\"nrmse +\"").find("column"), std::string::npos);
  EXPECT_NE(error("tune Lambda=1..2 budget=soon").find("budget 'soon'"), std::string::npos);
  EXPECT_NE(error("tune Lambda=1..2 budget=2.5").find("whole number"), std::string::npos);
  EXPECT_NE(error("tune Lambda=1..2 method=cmaes").find("bobyqa or neldermead"), std::string::npos);
  EXPECT_NE(error("tune Lambda=1..2 colour=red").find("unknown option 'colour'"), std::string::npos);
  EXPECT_NE(error("tune Lambda=1..2 fast").find("'fast' is neither"), std::string::npos);
  EXPECT_NE(error("tune Lambda=1..2 max_saturated=2").find("between 0 and 1"), std::string::npos);
}

// nrmse divides by the reference's range in the window: a window where the
// reference barely moves against the rig's task space is flagged, with what
// to change; one where it moves is not.
TEST(TuneMotion, AWindowWhereTheReferenceBarelyMovesIsFlagged) {
  RunMetrics still;
  still.has_true = true;
  still.truth.tracked = {0, 1, 2};
  still.ref_span = {0.1, 0.2, 0.3};
  still.y_span = {2.0, 2.5, 2.7};
  const std::vector<double> hasel = {23.0, 20.2, 19.2};
  const std::string w = still_reference_warning(still, hasel, 1, 5);
  EXPECT_NE(w.find("the reference barely moves in the scored window (1 s to 6 s of each run): it spans 0.3 of the "
                   "19.2 the rig's task space spans on y2 (1.6 %), while the output spans 2.7"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("--reference \"swirl hold=1\""), std::string::npos) << w;
  EXPECT_NE(w.find("--window"), std::string::npos) << w;
  RunMetrics moving = still;
  moving.ref_span = {0.1, 5.0, 0.2};
  EXPECT_EQ(still_reference_warning(moving, hasel, 0.5, 9), "");
  // An untracked axis that moves does not make the window score anything.
  RunMetrics untracked = still;
  untracked.truth.tracked = {1, 2};
  untracked.ref_span = {20.0, 0.2, 0.3};
  EXPECT_NE(still_reference_warning(untracked, hasel, 1, 5), "");
  // Without a task space only a reference that does not move at all is flagged.
  RunMetrics flat = still;
  flat.ref_span = {0, 0, 0};
  EXPECT_NE(still_reference_warning(flat, {}, 1, 5), "");
  EXPECT_EQ(still_reference_warning(still, {}, 1, 5), "");
}

TEST(TuneMetrics, InputEffortAndSaturationOverTheInputRange) {
  RunSeries s;
  s.n = 1;
  s.m = 2;
  s.has_u = true;
  // u0 steps 0 -> 0.5 -> 0 -> 0.5 on a range of 1; u1 sits at its upper limit.
  for (uint32_t k = 0; k < 4; ++k) {
    s.step.push_back(k);
    s.time_us.push_back(k * 1000);
    s.u.push_back(k % 2 ? 0.5f : 0.0f);
    s.u.push_back(2.0f);
  }
  RunRow run;
  run.loop_rate_hz = 1000;
  const RunMetrics m = run_metrics(run, s, {}, 0, InputLimits{{0.0f, -2.0f}, {1.0f, 2.0f}});
  // Changes: u0 0.5 each step over range 1, u1 none: RMS = sqrt(0.25 / 2).
  EXPECT_NEAR(m.u_effort, std::sqrt(0.125), 1e-9);
  // u0 at its lower limit half the time, u1 at its upper limit throughout.
  EXPECT_DOUBLE_EQ(m.u_saturated, 0.75);
  EXPECT_NEAR(*metric_value(m, "u_effort"), std::sqrt(0.125), 1e-9);
  EXPECT_TRUE(std::isnan(run_metrics(run, s, {}, 0).u_saturated)) << "no limits recorded: not known";
}

TEST(TunePlot, ObjectivePerEvaluationBestSoFarAndFailures) {
  TuneSessionRow s;
  s.id = 3;
  s.objective = "nrmse";
  s.space = "Lambda=0.01..100:log";
  s.method = "bobyqa";
  std::vector<TuneEvalRow> e(3);
  e[0].eval = 1, e[0].objective = 0.2;
  e[1].eval = 2, e[1].failed = "lost frames";
  e[2].eval = 3, e[2].objective = 0.05;
  const std::string g = tune_plot_script(s, e, ImageFormat::Svg);
  EXPECT_NE(g.find("1 0.2 0.2 NaN\n2 NaN 0.2 0\n3 0.05 0.05 NaN\n"), std::string::npos) << g;
  EXPECT_NE(g.find("best so far"), std::string::npos);
  EXPECT_NE(g.find("set logscale y"), std::string::npos);
  EXPECT_NE(g.find("tuning session 3: minimise nrmse"), std::string::npos);
  EXPECT_THROW(tune_plot_script(s, {}, ImageFormat::Svg), std::exception);
}

}  // namespace
}  // namespace nlsoft::console
