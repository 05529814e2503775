// A rig the code was never compiled for, through the real nlsoft-console:
// a rig file written here (not one of rigs/), with a generic plant of a
// clear nonlinearity, goes dataset -> train -> simulate and tracks.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/console/run_process.hpp"
#include "app/console/temp_dir.hpp"

namespace nlsoft::test {
namespace {

const std::string kConsole = NLSOFT_CONSOLE_BIN;

// Three actuators (a tanh-saturating one, a stiffening one with backlash, a
// hard stop), two outputs a camera measures, five sensors, 80 Hz.
const char* kArm = R"(name = "lab-arm"
description = "three actuators, two tracked outputs, five sensors"
rate_hz = 80.0
nd = 2
dd = 2

[[input]]
name = "a"
min = 0.0
max = 1.0
neutral = 0.5
pwm = "PC6"

[[input]]
name = "b"
min = -1.0
max = 1.0
neutral = 0.0
pwm = "PC7"

[[input]]
name = "c"
min = 0.0
max = 2.0
neutral = 1.0
pwm = "PC8"

[[output]]
name = "x"
unit = "mm"
min = -10.0
max = 10.0
source = "external"

[[output]]
name = "y"
unit = "mm"
min = -10.0
max = 10.0
source = "external"

[[sensor]]
name = "s1"
source = "adc"
adc = 0

[[sensor]]
name = "s2"
source = "adc"
adc = 1

[[sensor]]
name = "s3"
source = "adc"
adc = 4

[[sensor]]
name = "s4"
source = "adc"
adc = 6

[[sensor]]
name = "s5"
source = "adc"
adc = 7

[controller]
Q = [1e3, 1e3]
Lambda = [1.0, 1.0, 1.0]
s = 1e-20
b = 0.0
r = 400.0
N = 4
Nc = 2
eps = 1e-3
nr_max_iter = 2
feedback = "measured"

[plant]
kind = "generic"
coupling = [[3.0, 1.0, -0.5],
            [-0.5, 1.5, 2.0]]
output_offset = [0.0, 0.0]
output_tau = [0.0, 0.03]
sensor_map = [[1.0, 0.0, 0.0, 0.0, 0.0],
              [0.0, 1.0, 0.0, 0.0, 0.0],
              [0.0, 0.0, 1.0, 0.0, 0.0],
              [0.0, 0.0, 0.5, 1.0, 0.0],
              [0.2, 0.0, 0.0, 0.0, 1.0]]
sensor_noise = [0.01, 0.01, 0.01, 0.01, 0.01]

[[plant.actuator]]
gain = 8.0
shape = "tanh"
knee = 0.4
tau = 0.06

[[plant.actuator]]
gain = 4.0
shape = "power"
exponent = 2.0
play = 0.02
tau = 0.08

[[plant.actuator]]
gain = 3.0
shape = "saturation"
knee = 0.6
tau = 0.05
)";

void write(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

ProcessResult console(const std::string& args) { return run_process(shell_quote(kConsole) + " " + args); }

TEST(AnyRig, AGenericRigFileIsRecordedTrainedAndTracksAnInfinity) {
  TempDir dir;
  const std::string rig = dir.file("lab-arm.toml"), csv = dir.file("arm.csv"), model = dir.file("arm.nlsm");
  write(rig, kArm);

  ProcessResult r = console("dataset --rig " + shell_quote(rig) + " --out " + shell_quote(csv) + " --steps 24000");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("24000 samples of lab-arm (m=3 n=2 w=5, 300.0 s at 80 Hz)"), std::string::npos) << r.output;

  r = console("train --rig " + shell_quote(rig) + " --data " + shell_quote(csv) + " --out " + shell_quote(model));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("trained lab-arm model"), std::string::npos) << r.output;

  r = console("model info " + shell_quote(model));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("platform none, m=3 n=2 w=5 nd=2 dd=2"), std::string::npos) << r.output;

  r = console("simulate --rig " + shell_quote(rig) + " --model " + shell_quote(model) + " --reference infinity --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["rmse"].size(), 2u);
  EXPECT_EQ(j["samples"].get<long>(), 1600);  // 20 s at 80 Hz: two and a half 8 s laps
  // nRMSE against the output span (20 mm each), the worst axis.
  double worst = 0;
  for (const auto& e : j["rmse"]) worst = std::max(worst, e.get<double>() / 20.0);
  std::printf("lab-arm Infinity: nRMSE %.3f %% of the output span, %.3f %% of the reference's range\n", 100 * worst,
              100 * j["nrmse"].get<double>());
  EXPECT_LE(worst, 0.05);
  EXPECT_GT(worst, 0.0);
  // ... and against the reference's own range (what `simulate` reports), too.
  EXPECT_LE(j["nrmse"].get<double>(), 0.05);
}

}  // namespace
}  // namespace nlsoft::test
