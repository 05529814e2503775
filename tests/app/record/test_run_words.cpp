// What the console says of a run where a figure does not apply, on the real
// binary against nlsoft-firmware-sim: a run shorter than its reference's
// hold has no nrmse (said, not "nan"); an identification run tracks
// nothing (no tracking figure, not a 0) and a --sim-fast one kept no clock
// (its loop rate is not a share of the set one); `train` gives a run's
// length in control steps, not the --sim-fast firmware's clock, and notes
// inputs that took two levels only.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;

using test::run_process;
using test::shell_quote;

constexpr const char* kNotApplicable = "n/a (the reference held still; see nrmse_space)";

class RunWords : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }
  test::ProcessResult console(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args + " 2>&1");
  }
  std::string db() const { return dir_.file("runs.db"); }
  test::TempDir dir_;
};

// hasel's Swirl holds its first point 10 steps a point; `run 1s` of a
// Swirl held 1000 steps a point stays on that point.
TEST_F(RunWords, ARunShorterThanItsReferencesHoldSaysNrmseDoesNotApply) {
  const std::string script = dir_.file("still.nls");
  std::ofstream(script) << "ref swirl hold=1000\nrun 1s\n";
  auto r = console("--sim hasel --db " + shell_quote(db()) + " --script " + shell_quote(script));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, std::string("nrmse ") + kNotApplicable)) << r.output;
  EXPECT_FALSE(contains(r.output, "nan")) << r.output;

  r = console("runs show 1 --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, std::string("nrmse ") + kNotApplicable + " max error")) << r.output;
  EXPECT_FALSE(contains(r.output, "nan")) << r.output;
}

TEST_F(RunWords, AnIdentificationRunShowsNoTrackingFiguresAndTrainGivesItsLengthInSteps) {
  auto r = console("ident --sim hasel --signal prbs --duration 20s --sim-fast --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;

  r = console("runs list --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  std::istringstream rows(r.output);
  std::string row;
  while (std::getline(rows, row) && row.rfind("    1  ", 0) != 0) {
  }
  ASSERT_TRUE(contains(row, " ident ")) << r.output;
  EXPECT_FALSE(contains(row, "0.0000")) << "an ident run has no nrmse\n" << r.output;
  EXPECT_TRUE(contains(row, " - ")) << r.output;

  r = console("runs list --json --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(nlohmann::json::parse(r.output)[0]["nrmse"].is_null()) << r.output;

  r = console("runs show 1 --json --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  for (const char* k : {"nrmse", "max_error", "rmse", "nrmse_hat", "nrmse_space"})
    EXPECT_TRUE(j[k].is_null()) << k << ": " << j[k].dump();
  EXPECT_GT(j["loop_rate_hz"].get<double>(), 1.5 * j["loop_rate_set_hz"].get<double>())
      << "a --sim-fast simulator steps faster than its set rate";

  // Its loop rate: set 130 Hz, stepped as fast as the host went; not a share.
  r = console("runs show 1 --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "loop 130 Hz set, stepped as fast as the host ran it (")) << r.output;
  EXPECT_FALSE(contains(r.output, " %)")) << r.output;
  EXPECT_FALSE(contains(r.output, "tracking (")) << r.output;

  // 20 s of steps at 130 Hz, whatever the firmware's clock said (what
  // train says of its data, not its fit: one seed, a short refinement).
  r = console("train --rig hasel --run 1 --db " + shell_quote(db()) + " --epochs 1 --seeds 1 --lbfgs 50 --out " +
              shell_quote(dir_.file("h.nlsm")));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "  run 1: 2600 samples, 0 gaps, 20 s at 130 Hz;")) << r.output;
  // prbs drives every input between two levels, and train says what that costs.
  EXPECT_TRUE(contains(r.output, "note: u0, u1, u2, u3, u4 and u5 took two levels only")) << r.output;
}

}  // namespace
}  // namespace nlsoft::console
