// `nlsoft-console ident` end to end: the real console against the simulator
// of a rig file written here (not one of rigs/), a PRBS identification run
// of 60 s at the simulator's full speed, read back as a user would, through
// `runs show --json` and `runs export --csv`.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <random>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/support/process_tree.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sqlite.hpp"

namespace nlsoft::test {
namespace {

const std::string kConsole = NLSOFT_CONSOLE_BIN;

// Three inputs with asymmetric limits (one neutral at its lower limit), two
// outputs, four sensors, 100 Hz, a generic plant.
const char* kBench = R"(name = "ident-bench"
description = "a rig only this test knows"
rate_hz = 100.0
nd = 2
dd = 2

[[input]]
name = "a"
min = 0.0
max = 1.0
neutral = 0.0
pwm = "PC6"

[[input]]
name = "b"
min = -2.0
max = 6.0
neutral = 1.0
pwm = "PC7"

[[input]]
name = "c"
min = 10.0
max = 12.0
neutral = 11.0
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

[controller]
Q = [1e3, 1e3]
Lambda = [1.0, 1.0, 1.0]
s = 1e-20
b = 0.0
r = 400.0
N = 4
Nc = 2
eps = 1e-3
nr_max_iter = 1
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
              [0.0, 0.0, 0.5, 1.0, 0.0]]
sensor_noise = [0.01, 0.01, 0.01, 0.01]

[[plant.actuator]]
gain = 8.0
shape = "tanh"
knee = 0.4
tau = 0.06

[[plant.actuator]]
gain = 4.0
shape = "power"
exponent = 2.0
tau = 0.08

[[plant.actuator]]
gain = 3.0
shape = "saturation"
knee = 0.6
tau = 0.05
)";
const double kMin[3] = {0.0, -2.0, 10.0}, kMax[3] = {1.0, 6.0, 12.0};

ProcessResult console(const std::string& args) { return run_process(shell_quote(kConsole) + " " + args); }

std::vector<std::vector<std::string>> read_csv(const std::string& path, std::vector<std::string>& head) {
  std::ifstream f(path);
  std::string line;
  std::vector<std::vector<std::string>> rows;
  auto split = [](const std::string& l) {
    std::vector<std::string> cells;
    std::stringstream ss(l);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    if (!l.empty() && l.back() == ',') cells.emplace_back();
    return cells;
  };
  if (std::getline(f, line)) head = split(line);
  while (std::getline(f, line)) rows.push_back(split(line));
  return rows;
}

int column(const std::vector<std::string>& head, const std::string& name) {
  for (size_t i = 0; i < head.size(); ++i)
    if (head[i] == name) return int(i);
  ADD_FAILURE() << "no column " << name;
  return 0;
}

struct Ident {
  TempDir dir;
  std::string rig = dir.file("ident-bench.toml"), db = dir.file("runs.db");
  Ident() { std::ofstream(rig) << kBench; }
  ProcessResult run(const std::string& args) {
    return console("ident --sim " + shell_quote(rig) + " --sim-fast --db " + shell_quote(db) + " " + args);
  }
  std::vector<std::vector<std::string>> exported(int run, std::vector<std::string>& head) {
    const std::string csv = dir.file("run" + std::to_string(run) + ".csv");
    const ProcessResult r = console("runs export " + std::to_string(run) + " --csv " + shell_quote(csv) + " --db " +
                                    shell_quote(db));
    EXPECT_EQ(r.code, 0) << r.output;
    return read_csv(csv, head);
  }
};

TEST(IdentE2E, APrbsRunOfARigFileIsRecordedWholeInsideItsLimitsWithSensorsAndMeasuredOutputs) {
  Ident t;
  const ProcessResult r = t.run("--signal prbs --duration 60s");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("a simulated line carries every step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("6000 samples of 6000 steps"), std::string::npos) << r.output;

  const ProcessResult show = console("runs show 1 --json --db " + shell_quote(t.db));
  ASSERT_EQ(show.code, 0) << show.output;
  const auto j = nlohmann::json::parse(show.output.substr(show.output.find('{')));
  EXPECT_EQ(j["kind"], "ident");
  EXPECT_EQ(j["w"], 4);
  EXPECT_EQ(j["excitation"]["signal"], "prbs");
  EXPECT_EQ(j["excitation"]["duration_steps"], 6000);
  EXPECT_EQ(j["samples"], 6000);  // rate x duration
  EXPECT_EQ(j["lost_frames"], 0);

  std::vector<std::string> head;
  const auto rows = t.exported(1, head);
  ASSERT_EQ(rows.size(), 6000u);
  const int step = column(head, "step"), u0 = column(head, "u0"), y0 = column(head, "y_true0"),
            l0 = column(head, "l0");
  EXPECT_EQ(column(head, "l3"), l0 + 3);
  double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
  for (size_t k = 0; k < rows.size(); ++k) {
    const auto& row = rows[k];
    ASSERT_EQ(row.size(), head.size()) << "row " << k;
    ASSERT_EQ(std::stoul(row[size_t(step)]), k);
    for (int i = 0; i < 3; ++i) {
      const double u = std::stod(row[size_t(u0 + i)]);
      ASSERT_GE(u, kMin[i]) << "row " << k;
      ASSERT_LE(u, kMax[i]) << "row " << k;
      lo[i] = std::min(lo[i], u), hi[i] = std::max(hi[i], u);
    }
    for (int j2 = 0; j2 < 2; ++j2) ASSERT_TRUE(std::isfinite(std::stod(row[size_t(y0 + j2)]))) << "row " << k;
    for (int s = 0; s < 4; ++s) ASSERT_TRUE(std::isfinite(std::stod(row[size_t(l0 + s)]))) << "row " << k;
  }
  // PRBS: two levels per input, 0.8 of the range apart (the default amplitude).
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(hi[i] - lo[i], 0.8 * (kMax[i] - kMin[i]), 1e-4) << "input " << i;
  // The outputs moved with the inputs.
  double ymin = 1e9, ymax = -1e9;
  for (const auto& row : rows) ymin = std::min(ymin, std::stod(row[size_t(y0)])), ymax = std::max(ymax, std::stod(row[size_t(y0)]));
  EXPECT_GT(ymax - ymin, 1.0);
}

// A rig file's [ident] sets what the words leave out: this bench's prbs
// spans half of each range, and ident says where that came from.
TEST(IdentE2E, ARigFilesIdentTableSetsTheAmplitudeTheWordsLeaveOut) {
  Ident t;
  std::ofstream(t.rig, std::ios::app) << "\n[ident.prbs]\namplitude = 0.5\n";
  const ProcessResult r = t.run("--signal prbs --duration 10s");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("excitation: prbs, band 0.05:2 Hz (ident's default), amplitude 0.5 ([ident.prbs] of " + t.rig +
                          "), seed 1"),
            std::string::npos)
      << r.output;
  std::vector<std::string> head;
  const auto rows = t.exported(1, head);
  ASSERT_EQ(rows.size(), 1000u);
  const int u0 = column(head, "u0");
  for (int i = 0; i < 3; ++i) {
    double lo = 1e9, hi = -1e9;
    for (const auto& row : rows) lo = std::min(lo, std::stod(row[size_t(u0 + i)])), hi = std::max(hi, std::stod(row[size_t(u0 + i)]));
    EXPECT_NEAR(hi - lo, 0.5 * (kMax[i] - kMin[i]), 1e-4) << "input " << i;
  }
}

// How many different values an input took (prbs: two).
size_t distinct_levels(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return size_t(std::unique(v.begin(), v.end()) - v.begin());
}

// Without --signal a run is aprbs: a model trained from it sees levels
// inside each input's range, which prbs's two never show it.
TEST(IdentE2E, ARunWithoutASignalIsAprbsWithManyLevelsPerInput) {
  Ident t;
  const ProcessResult r = t.run("--duration 30s");
  ASSERT_EQ(r.code, 0) << r.output;
  const ProcessResult show = console("runs show 1 --json --db " + shell_quote(t.db));
  ASSERT_EQ(show.code, 0) << show.output;
  const auto j = nlohmann::json::parse(show.output.substr(show.output.find('{')));
  EXPECT_EQ(j["excitation"]["signal"], "aprbs");
  std::vector<std::string> head;
  const auto rows = t.exported(1, head);
  ASSERT_EQ(rows.size(), 3000u);
  const int u0 = column(head, "u0");
  for (int i = 0; i < 3; ++i) {
    std::vector<double> u;
    for (const auto& row : rows) u.push_back(std::stod(row[size_t(u0 + i)]));
    EXPECT_GT(distinct_levels(u), 10u) << "input " << i;
  }
}

// aprbs mixed: many levels per input (not prbs's two), and the inputs move
// together around a shared level; the run records both words.
TEST(IdentE2E, AnAprbsMixedRunRecordsManyLevelsPerInputMovingTogether) {
  Ident t;
  const ProcessResult r = t.run("--signal aprbs --mixed --duration 60s --band 0.1:10 --amplitude 1");
  ASSERT_EQ(r.code, 0) << r.output;
  const ProcessResult show = console("runs show 1 --json --db " + shell_quote(t.db));
  ASSERT_EQ(show.code, 0) << show.output;
  const auto j = nlohmann::json::parse(show.output.substr(show.output.find('{')));
  EXPECT_EQ(j["excitation"]["signal"], "aprbs");
  EXPECT_EQ(j["excitation"]["mixed"], true);
  std::vector<std::string> head;
  const auto rows = t.exported(1, head);
  ASSERT_EQ(rows.size(), 6000u);
  const int u0 = column(head, "u0");
  std::vector<double> x[3];
  for (const auto& row : rows)
    for (int i = 0; i < 3; ++i) x[i].push_back((std::stod(row[size_t(u0 + i)]) - kMin[i]) / (kMax[i] - kMin[i]));
  for (int i = 0; i < 3; ++i) EXPECT_GT(distinct_levels(x[i]), 100u) << "input " << i;
  auto corr = [](const std::vector<double>& a, const std::vector<double>& b) {
    double ma = 0, mb = 0;
    for (size_t k = 0; k < a.size(); ++k) ma += a[k] / double(a.size()), mb += b[k] / double(b.size());
    double ab = 0, aa = 0, bb = 0;
    for (size_t k = 0; k < a.size(); ++k) ab += (a[k] - ma) * (b[k] - mb), aa += (a[k] - ma) * (a[k] - ma), bb += (b[k] - mb) * (b[k] - mb);
    return ab / std::sqrt(aa * bb);
  };
  EXPECT_GT(corr(x[0], x[1]), 0.4);
  EXPECT_GT(corr(x[0], x[2]), 0.4);
}

TEST(IdentE2E, TheSameSeedRecordsTheSameInputsAndAnotherSeedOthers) {
  Ident t;
  for (const char* seed : {"5", "5", "6"}) {
    const ProcessResult r = t.run(std::string("--signal steps --duration 5s --band 0.5:5 --seed ") + seed);
    ASSERT_EQ(r.code, 0) << r.output;
  }
  std::vector<std::string> head;
  auto inputs = [&](int run) {
    std::vector<std::string> u;
    const auto rows = t.exported(run, head);
    const int u0 = column(head, "u0");
    for (const auto& row : rows)
      for (int i = 0; i < 3; ++i) u.push_back(row[size_t(u0 + i)]);
    return u;
  };
  const auto a = inputs(1), b = inputs(2), c = inputs(3);
  ASSERT_EQ(a.size(), 1500u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(IdentE2E, BadWordsAreRefusedInWordsBeforeAnythingIsRecorded) {
  Ident t;
  const struct {
    const char* args;
    const char* says;
  } cases[] = {
      // An unknown name, answered with the names there are.
      {"--signal sine --duration 5s", "sine not in {steps,prbs,walk,chirp,aprbs}"},
      {"--signal prbs --mixed --duration 5s", "prbs has only +-1"},
      {"--signal aprbs --mixed --joint --duration 5s", "--joint excludes --mixed"},
      {"--duration 5s --amplitude 1.5", "outside (0, 1]"},
      {"--duration 5s --band 3:1", "the lower edge is above the upper one"},
      {"--duration 5s --band fast", "is not LO:HI"},
      {"--duration 5 --band 0.1:1", "needs a unit"},
      {"--duration 5s --band 0.1:60", "reaches past half the loop rate (50 Hz at 100 Hz)"},
  };
  for (const auto& c : cases) {
    const ProcessResult r = t.run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
  }
  const ProcessResult list = console("runs list --json --db " + shell_quote(t.db));
  EXPECT_EQ(list.output.find("\"kind\": \"ident\""), std::string::npos) << list.output;
}

// The script's `ident` line runs the same identification run.
TEST(IdentE2E, AScriptsIdentLineRecordsAnIdentificationRun) {
  Ident t;
  const std::string script = t.dir.file("ident.nls");
  std::ofstream(script) << "ident walk 3s seed=9 band=0.2:4 label=scripted\nexpect lost_frames == 0\n";
  std::ofstream(t.rig, std::ios::app) << "\n[ident]\namplitude = 0.5\n";
  const ProcessResult r = console("--sim " + shell_quote(t.rig) + " --sim-fast --db " + shell_quote(t.db) +
                                  " --script " + shell_quote(script));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("identification run: 300 of 300 steps recorded"), std::string::npos) << r.output;
  // The line's words, then the rig file's [ident], as the command takes them.
  EXPECT_NE(r.output.find("excitation: walk, band 0.2:4 Hz (--band), amplitude 0.5 ([ident] of " + t.rig + "), seed 9"),
            std::string::npos)
      << r.output;
  console::RunStore store(t.db);
  const console::RunRow run = store.run(1);
  EXPECT_EQ(run.kind, "ident");
  EXPECT_EQ(run.label, "scripted");
  EXPECT_EQ(run.samples, 300u);
  EXPECT_NE(run.excitation.find("\"signal\":\"walk\""), std::string::npos) << run.excitation;
}

// Ctrl-C in the middle of a real-time run: the run stops, and what was
// recorded stays, sensors and all, with the signal named as its end.
TEST(IdentE2E, CtrlCStopsTheRunAndKeepsWhatWasRecorded) {
  Ident t;
  const std::string out = t.dir.file("console.out");
  const pid_t pid = start_shell("exec " + shell_quote(kConsole) + " ident --sim " + shell_quote(t.rig) + " --db " +
                                shell_quote(t.db) + " --signal walk --duration 60s >" + shell_quote(out) + " 2>&1");
  ASSERT_GT(pid, 0);
  bool recording = false;
  for (int i = 0; i < 600 && !recording; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    try {
      const auto runs = console::RunStore(t.db).list();
      recording = !runs.empty() && runs[0].samples > 0;
    } catch (const std::exception&) {
    }
  }
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_TRUE(recording) << text;
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 2) << text;
  EXPECT_NE(text.find("interrupted by SIGINT (Ctrl-C): run 1 stopped and kept"), std::string::npos) << text;
  console::RunStore store(t.db);
  const console::RunRow r = store.run(1);
  EXPECT_EQ(r.kind, "ident");
  EXPECT_EQ(r.end_reason, "interrupted by SIGINT (Ctrl-C)");
  EXPECT_GT(r.samples, 0u);
  EXPECT_LT(r.samples, 6000u);
  const console::RunSeries series = store.series(1);
  EXPECT_EQ(series.rows(), r.samples);
  EXPECT_TRUE(series.has_l);
  EXPECT_EQ(series.l.size(), 4 * series.rows());
}


// A motion capture of the outputs, on a clock of its own: a simulated run's
// outputs (which the simulator measures) written as a capture 0.734 s
// ahead of the run's clock, starting 1 s before the run, at noise 0.02;
// the run's y_true wiped, the capture merged: the offset is estimated from
// the run's inputs and sensors alone, and y_true comes back within the noise.
struct Captured {
  std::vector<double> t, y0, y1;  // the run's time (step / 100 Hz) and outputs
};

Captured outputs_of(Ident& t, int run) {
  std::vector<std::string> head;
  const auto rows = t.exported(run, head);
  const int step = column(head, "step"), y0 = column(head, "y_true0");
  Captured c;
  for (const auto& row : rows) {
    c.t.push_back(std::stod(row[size_t(step)]) / 100.0);
    c.y0.push_back(row[size_t(y0)].empty() ? std::nan("") : std::stod(row[size_t(y0)]));
    c.y1.push_back(row[size_t(y0) + 1].empty() ? std::nan("") : std::stod(row[size_t(y0) + 1]));
  }
  return c;
}

// Writes the capture: `before` rows at the first value ahead of the run, at
// the run's sample spacing, then the run's outputs, time shifted by offset.
void write_capture(const std::string& path, const Captured& c, double offset, double noise, const char* header) {
  std::mt19937 rng(7);
  std::normal_distribution<double> e(0.0, noise);
  std::ofstream f(path);
  f << header << "\n";
  char line[128];
  for (int k = -100; k < int(c.t.size()); ++k) {
    const size_t i = size_t(std::max(k, 0));
    std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f\n", k * 0.01 + offset, c.y0[i] + e(rng), c.y1[i] + e(rng));
    f << line;
  }
}

double offset_said(const std::string& out) {
  const std::string key = "capture clock offset estimated: ";
  const size_t at = out.find(key);
  if (at == std::string::npos) return std::nan("");
  return std::stod(out.substr(at + key.size()));
}

double rms_difference(const Captured& a, const Captured& b) {
  double sum = 0;
  for (size_t k = 0; k < a.t.size(); ++k)
    sum += (a.y0[k] - b.y0[k]) * (a.y0[k] - b.y0[k]) + (a.y1[k] - b.y1[k]) * (a.y1[k] - b.y1[k]);
  return std::sqrt(sum / double(2 * a.t.size()));
}

TEST(IdentE2E, AMotionCaptureOnItsOwnClockIsPlacedOnTheRunAndBecomesItsMeasuredOutputs) {
  Ident t;
  ASSERT_EQ(t.run("--signal prbs --duration 60s").code, 0);
  const Captured truth = outputs_of(t, 1);
  ASSERT_EQ(truth.t.size(), 6000u);
  const std::string cap = t.dir.file("mocap.csv");
  const double kOffset = 0.734, kNoise = 0.02;
  // The columns by the rig's output names, in another order than the run's.
  write_capture(cap, truth, kOffset, kNoise, "time,y0,y1");
  {
    console::Db db(t.db, console::Db::Access::ReadWrite);
    db.exec("UPDATE samples SET y_true=NULL");
  }
  // Without its outputs the run says it has nothing to train from.
  const ProcessResult bare = console("runs show 1 --db " + shell_quote(t.db));
  EXPECT_NE(bare.output.find("no measured output (y_true): nothing to train a model from until one is merged"),
            std::string::npos)
      << bare.output;
  const ProcessResult merged = console("runs merge-y 1 " + shell_quote(cap) + " --db " + shell_quote(t.db));
  ASSERT_EQ(merged.code, 0) << merged.output;
  const double est = offset_said(merged.output);
  std::printf("capture clock offset: true %+.4f s, estimated %+.4f s\n", kOffset, est);
  EXPECT_NEAR(est, kOffset, 0.01) << merged.output;  // within one sample period (100 Hz)
  EXPECT_NE(merged.output.find("6,000 of 6,100 capture rows inside the run"), std::string::npos) << merged.output;
  EXPECT_NE(merged.output.find("y_true) of 6,000 of 6,000 samples set"), std::string::npos) << merged.output;
  const Captured back = outputs_of(t, 1);
  const double rms = rms_difference(back, truth);
  std::printf("y_true restored: rms difference %.4f (capture noise %.4f)\n", rms, kNoise);
  EXPECT_LT(rms, 2 * kNoise);

  // The offset given: the same samples, exactly where they belong.
  const ProcessResult given =
      console("runs merge-y 1 " + shell_quote(cap) + " --offset 0.734 --db " + shell_quote(t.db));
  ASSERT_EQ(given.code, 0) << given.output;
  EXPECT_NE(given.output.find("capture clock offset given: +0.734 s (run time = capture time - 0.734 s)"),
            std::string::npos)
      << given.output;
  EXPECT_LT(rms_difference(outputs_of(t, 1), truth), 1.2 * kNoise);

  // ident --y-from: the same inputs again (same seed), the capture merged
  // at the end of the run, its columns named for the rig's outputs.
  write_capture(cap, truth, kOffset, kNoise, "time,x,y");
  const ProcessResult r = t.run("--signal prbs --duration 60s --y-from " + shell_quote(cap));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NEAR(offset_said(r.output), kOffset, 0.01) << r.output;
  EXPECT_NE(r.output.find("run 2: measured outputs (y_true) of 6,000 of 6,000 samples set"), std::string::npos)
      << r.output;
  EXPECT_LT(rms_difference(outputs_of(t, 2), truth), 2 * kNoise);
}

// Each bad capture: exit 2, the file and line named, the run as it was.
TEST(IdentE2E, ABadCaptureIsRefusedNamingItsLineAndTheRunIsUnchanged) {
  Ident t;
  ASSERT_EQ(t.run("--signal steps --duration 5s --band 0.5:5").code, 0);
  const std::string before = t.dir.file("before.csv"), after = t.dir.file("after.csv");
  auto export_to = [&](const std::string& f) {
    const ProcessResult r = console("runs export 1 --csv " + shell_quote(f) + " --db " + shell_quote(t.db));
    EXPECT_EQ(r.code, 0) << r.output;
    std::ifstream in(f);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string was = export_to(before);
  const struct {
    const char* text;
    const char* offset;
    const char* says;
  } cases[] = {
      {"time,y0\n0,1\n0.1,2\n", "", "bad.csv:1: no column for output y1 (y)"},
      {"time,y0,y1,z\n0,1,2,3\n0.1,2,3,4\n", "", "bad.csv:1: column 4 ('z') is no output of this run"},
      {"t,y0,y1\n0,1,2\n0.1,2,3\n", "", "bad.csv:1: the first column must be 'time'"},
      {"time,y0,y1\n0,1,2\n0.1,2,3\n\n0.3,1,1\n0.2,1,1\n", "",
       "bad.csv:6: time 0.2 s is not after the previous row's 0.3 s (line 5)"},
      {"time,y0,y1\n0,1,2\n0.1,nan,3\n", "", "bad.csv:3: column 2 ('y0'): not a finite number: 'nan'"},
      {"time,y0,y1\n0,1,2\n0.1,2\n", "", "bad.csv:3: expected 3 values, found 2"},
      {"time,y0,y1\n0,1,2\n1,2,3\n", " --offset 100", "does not overlap run 1"},
  };
  const std::string bad = t.dir.file("bad.csv");
  for (const auto& c : cases) {
    std::ofstream(bad) << c.text;
    const ProcessResult r =
        console("runs merge-y 1 " + shell_quote(bad) + c.offset + " --rig " + shell_quote(t.rig) + " --db " + shell_quote(t.db));
    EXPECT_EQ(r.code, 2) << c.text << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.text << "\n" << r.output;
    EXPECT_EQ(export_to(after), was) << c.text;
  }
}

}  // namespace
}  // namespace nlsoft::test
