// A rig the code was never compiled for, through the real nlsoft-console:
// a rig file written here (not one of rigs/), with a generic plant of a
// clear nonlinearity, goes dataset -> train -> simulate and tracks.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::test {
namespace {

const std::string kConsole = NLSOFT_CONSOLE_BIN;

// Three actuators (a tanh-saturating one, a stiffening one with backlash, a
// hard stop), two outputs a camera measures, five sensors, 80 Hz.

void write(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

ProcessResult console(const std::string& args) { return run_process(shell_quote(kConsole) + " " + args); }

TEST(AnyRig, AGenericRigFileIsRecordedTrainedAndTracksAnInfinity) {
  TempDir dir;
  const std::string rig = dir.file("lab-arm.toml"), csv = dir.file("arm.csv"), model = dir.file("arm.nlsm");
  std::ifstream fixture(NLSOFT_STAGE_RIG);
  ASSERT_TRUE(fixture) << NLSOFT_STAGE_RIG;
  write(rig, std::string(std::istreambuf_iterator<char>(fixture), {}));

  ProcessResult r = console("dataset --rig " + shell_quote(rig) + " --out " + shell_quote(csv) + " --steps 24000");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("24000 samples of stage (m=3 n=2 w=5, 300.0 s at 80 Hz)"), std::string::npos) << r.output;

  // A bounded budget: what is tested is the path, not the defaults' budget
  // (the docs test runs those), and a sanitizer build runs it ten times slower.
  r = console("train --rig " + shell_quote(rig) + " --data " + shell_quote(csv) + " --out " + shell_quote(model) +
              " --seeds 1 --lbfgs 200");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("trained stage model"), std::string::npos) << r.output;

  r = console("model info " + shell_quote(model));
  ASSERT_EQ(r.code, 0) << r.output;
  // The rig the model is of, by the name its file gives it.
  EXPECT_NE(r.output.find("rig stage (a rig file), m=3 n=2 w=5 nd=2 dd=2"), std::string::npos) << r.output;

  r = console("simulate --rig " + shell_quote(rig) + " --model " + shell_quote(model) + " --reference infinity --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["rmse"].size(), 2u);
  EXPECT_EQ(j["samples"].get<long>(), 1600);  // 20 s at 80 Hz: two and a half 8 s laps
  // nRMSE against the output span (20 mm each), the worst axis.
  double worst = 0;
  for (const auto& e : j["rmse"]) worst = std::max(worst, e.get<double>() / 20.0);
  std::printf("stage Infinity: nRMSE %.3f %% of the output span, %.3f %% of the reference's range\n", 100 * worst,
              100 * j["nrmse"].get<double>());
  EXPECT_LE(worst, 0.05);
  EXPECT_GT(worst, 0.0);
  // ... and against the reference's own range (what `simulate` reports), too.
  EXPECT_LE(j["nrmse"].get<double>(), 0.05);
}

}  // namespace
}  // namespace nlsoft::test
