// `train --run ID` and `train --data EXPORT.csv` on runs a real console
// session recorded against nlsoft-firmware-sim: the model it writes runs
// the rig, a run and its export are the same training set, and runs that
// cannot train a model (no measured output, another rig, no samples, a
// file that is no training data) are refused, exit 2, naming the run or
// the file, with nothing written.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sample.hpp"
#include "shared/crc32.hpp"
#include "shared/model_file.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;

using test::run_process;
using test::shell_quote;

// The line of `text` that starts with `prefix` (empty if none).
std::string line_of(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) return line;
  return "";
}

// What follows the first ':' of a line ("  run 1: 2000 samples, ..." -> " 2000 samples, ...").
std::string after_colon(const std::string& line) {
  const size_t c = line.find(": ");
  return c == std::string::npos ? line : line.substr(c);
}

class TrainRuns : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }
  test::ProcessResult console(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args);
  }
  std::string db() const { return dir_.file("runs.db"); }
  // Run 1: msd under its shipped model following the rig's steps; the
  // simulator measures the output, so the run holds y_true.
  void record_msd() {
    const std::string script = dir_.file("s.nls");
    std::ofstream(script) << "run 3s label=ident\n";
    const auto r = console("--sim msd --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  // Runs the Recorder writes as a console would for a firmware that
  // measures no output (1), for another rig (2), and one with no samples (3).
  void record_unusable() {
    Recorder rec(db());
    auto run = [&](const std::string& rig, int samples, bool y_true) {
      RunInfo ri;
      ri.platform = rig;
      ri.n = 1;
      ri.m = 1;
      ri.loop_rate_hz = 1000;
      const int64_t id = rec.begin_run(ri);
      for (int k = 0; k < samples; ++k) {
        Sample s;
        s.k = uint64_t(k);
        s.n = 1;
        s.m = 1;
        s.step = uint32_t(100 + k);
        s.time_us = uint32_t(1000 * k);
        s.mask = protocol::telemetry_field::kStep | protocol::telemetry_field::kTime | protocol::telemetry_field::kU |
                 protocol::telemetry_field::kYHat | (y_true ? protocol::telemetry_field::kYTrue : 0);
        s.u()[0] = float(k % 7);
        s.y_hat()[0] = float(k) * 0.01f;
        s.y_true()[0] = float(k) * 0.01f;
        rec.add_sample(id, s);
      }
      rec.end_run(id, "completed", uint64_t(samples), 0);
      return id;
    };
    run("msd", 500, false);
    run("hasel", 500, true);
    run("msd", 0, true);
    rec.flush();
  }
  test::TempDir dir_;
};

TEST_F(TrainRuns, ARecordedRunTrainsAModelThatTracksTheRig) {
  record_msd();
  const std::string model = dir_.file("msd-run.nlsm");
  auto r = console("train --rig msd --run 1 --db " + shell_quote(db()) + " --out " + shell_quote(model));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "training on 1 run of rig msd: ")) << r.output;
  EXPECT_TRUE(contains(r.output, "wrote " + model)) << r.output;

  r = console("simulate --rig msd --model " + shell_quote(model) + " --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["rmse"].size(), 1u);
  // The paper's steps (0.5, 1 and 2 m, 30 s), tracked by a model learnt
  // from three seconds of one closed-loop run: within 5 % of the
  // reference's range, as with the shipped model (3.5 %).
  std::printf("msd steps with the model trained from run 1: nRMSE %.3f %%\n", 100 * j["nrmse"].get<double>());
  EXPECT_LT(j["nrmse"].get<double>(), 0.05) << r.output;
  EXPECT_GT(j["nrmse"].get<double>(), 0.0) << r.output;
}

TEST_F(TrainRuns, AnExportedRunIsTheSameTrainingSetAsTheRun) {
  record_msd();
  const std::string csv = dir_.file("run1.csv"), a = dir_.file("a.nlsm"), b = dir_.file("b.nlsm");
  auto r = console("runs export 1 --csv " + shell_quote(csv) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  const auto from_run = console("train --rig msd --run 1 --db " + shell_quote(db()) + " --out " + shell_quote(a));
  ASSERT_EQ(from_run.code, 0) << from_run.output;
  const auto from_csv = console("train --rig msd --data " + shell_quote(csv) + " --out " + shell_quote(b));
  ASSERT_EQ(from_csv.code, 0) << from_csv.output;
  // Sample count, gaps, first and last rows, as each names them.
  const std::string run_line = line_of(from_run.output, "  run 1: ");
  const std::string csv_line = line_of(from_csv.output, "  " + csv + ": ");
  ASSERT_FALSE(run_line.empty()) << from_run.output;
  ASSERT_FALSE(csv_line.empty()) << from_csv.output;
  EXPECT_EQ(after_colon(run_line), after_colon(csv_line));
  EXPECT_TRUE(contains(run_line, " samples, 0 gaps, ")) << run_line;
  // The same rows train the same model, bit for bit.
  const std::string hash_a = line_of(from_run.output, "wrote ").substr(("wrote " + a).size());
  const std::string hash_b = line_of(from_csv.output, "wrote ").substr(("wrote " + b).size());
  EXPECT_EQ(hash_a, hash_b);
  EXPECT_TRUE(contains(hash_a, "hash 0x")) << from_run.output;
}

// Protocol 1.6: a closed-loop run of hasel, whose model reads 18 sensors,
// holds them (the console turns SENSOR_STREAM on), so it trains a model
// alone or with others, and `model fit` judges a model on it as far ahead
// as its controller looked (N = 3 as the run started). A run that holds
// no sensors (a 1.5 firmware's) is refused, saying why.
TEST_F(TrainRuns, AClosedLoopRunOfARigWithSensorsTrainsAndIsJudgedAtItsHorizon) {
  const std::string script = dir_.file("swirl.nls");
  std::ofstream(script) << "ref swirl\nrun 10s label=swirl\n";
  auto r = console("--sim hasel --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string csv = dir_.file("swirl.csv");
  r = console("runs export 1 --csv " + shell_quote(csv) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(csv);
  std::string header, row;
  ASSERT_TRUE(std::getline(in, header));
  ASSERT_TRUE(std::getline(in, row));
  EXPECT_TRUE(contains(header, ",l0,") && contains(header, ",l17")) << header;
  EXPECT_FALSE(contains(header, ",l18")) << header;

  const std::string model = dir_.file("swirl.nlsm");
  r = console("train --rig hasel --run 1 --db " + shell_quote(db()) + " --out " + shell_quote(model) + " --seeds 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "training on 1 run of rig hasel: ")) << r.output;
  EXPECT_TRUE(contains(r.output, "wrote " + model)) << r.output;

  r = console("model fit " + shell_quote(model) + " --run 1 --db " + shell_quote(db()) + " --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["runs"].size(), 1u);
  EXPECT_EQ(j["runs"][0]["horizon"], 3);
  ASSERT_EQ(j["runs"][0]["outputs"].size(), 3u);
  for (const auto& o : j["runs"][0]["outputs"]) {
    const double one = o["one_step"]["rmse"], ahead = o["k_step"]["rmse"];
    EXPECT_GT(ahead, 0.0) << o.dump();
    EXPECT_TRUE(std::isfinite(ahead)) << o.dump();
    EXPECT_GE(ahead, one) << o.dump();
  }
  r = console("model fit " + shell_quote(model) + " --run 1 --db " + shell_quote(db()) + " --horizon 0");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(contains(r.output, "3-step")) << r.output;  // one-step and free-run only
  EXPECT_TRUE(contains(r.output, "one-step")) << r.output;

  // The same rig's run without sensors, as a 1.5 firmware's: refused by name.
  {
    Recorder rec(db());
    RunInfo ri;
    ri.platform = "hasel";
    ri.n = 3;
    ri.m = 6;
    ri.loop_rate_hz = 130;
    const int64_t id = rec.begin_run(ri);
    Sample s;
    s.n = 3;
    s.m = 6;
    s.mask = protocol::telemetry_field::kStep | protocol::telemetry_field::kU | protocol::telemetry_field::kYTrue;
    for (int k = 0; k < 50; ++k) {
      s.k = uint64_t(k);
      s.step = uint32_t(k);
      rec.add_sample(id, s);
    }
    rec.end_run(id, "completed", 50, 0);
    rec.flush();
  }
  r = console("train --rig hasel --run 1 --run 2 --db " + shell_quote(db()) + " --out " + shell_quote(dir_.file("x.nlsm")));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "run 2 holds no sensor readings l, and rig 'hasel' has 18 sensors")) << r.output;
  EXPECT_FALSE(std::ifstream(dir_.file("x.nlsm")).good());
}

TEST_F(TrainRuns, RunsThatCannotTrainAModelAreRefusedByName) {
  record_unusable();
  const std::string out = dir_.file("never.nlsm");
  const std::string bad_csv = dir_.file("other.csv");
  std::ofstream(bad_csv) << "when,u0,y0\n0,1,2\n";
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"--run 1 --db " + shell_quote(db()), "run 1 has no measured output (y_true)"},
      {"--run 2 --db " + shell_quote(db()), "run 2 was recorded on rig 'hasel', not on rig 'msd'"},
      {"--run 3 --db " + shell_quote(db()), "run 3 has no samples"},
      {"--run 9 --db " + shell_quote(db()), "no run 9"},
      {"--data " + shell_quote(bad_csv), bad_csv + ": not training data: the header must start with 'time'"},
      {"", "give the data to train on: --run ID"},
  };
  for (const Case& c : cases) {
    const auto r = console("train --rig msd " + c.args + " --out " + shell_quote(out));
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, c.message)) << c.args << "\n" << r.output;
    EXPECT_FALSE(std::ifstream(out).good()) << c.args;
  }
}

// The fit train prints is kept in the model file after the model, `model
// info` shows it, and the model is what a firmware gets: the hash train
// names is the CRC of the model's own bytes, and a session's `model upload`
// of the file puts that hash in force (and in the runs recorded after it).
// --validate-run holds a whole run out for the fit; --nd/--dd set the lags
// within what the controller holds; a run with a gap (the firmware's step
// count jumps) trains with the gap said.
TEST_F(TrainRuns, AValidationRunLagsAndAGapAreTheRunsAndTheUsers) {
  const std::string script = dir_.file("two.nls");
  std::ofstream(script) << "run 1s label=a\nrun 1s label=b\n";
  auto r = console("--sim msd --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string model = dir_.file("v.nlsm");
  r = console("train --rig msd --run 1 --validate-run 2 --nd 3 --dd 3 --db " + shell_quote(db()) + " --out " +
              shell_quote(model));
  ASSERT_EQ(r.code, 0) << r.output;
  const uint64_t second = RunStore(db()).run(2).samples;
  EXPECT_TRUE(contains(r.output, "fit on held-out data of rig msd: run 2, whole (" + std::to_string(second - 3) +
                                     " rows)"))
      << r.output;
  EXPECT_TRUE(contains(r.output, "nd = 3, dd = 3")) << r.output;
  r = console("model info " + shell_quote(model));
  EXPECT_TRUE(contains(r.output, "m=1 n=1 w=0 nd=3 dd=3")) << r.output;

  for (const std::string& bad : {std::string("--run 1 --validate-run 1"), std::string("--run 1 --nd 33")}) {
    r = console("train --rig msd " + bad + " --db " + shell_quote(db()) + " --out " + shell_quote(dir_.file("n.nlsm")));
    EXPECT_EQ(r.code, 2) << bad << "\n" << r.output;
  }

  {
    Recorder rec(db());
    RunInfo ri;
    ri.platform = "msd";
    ri.n = ri.m = 1;
    ri.loop_rate_hz = 1000;
    const int64_t id = rec.begin_run(ri);
    for (int k = 0; k < 600; ++k) {
      Sample s;
      s.k = uint64_t(k);
      s.n = s.m = 1;
      s.step = uint32_t(k < 300 ? k : k + 40);  // 40 steps lost after sample 299
      s.time_us = s.step * 1000u;
      s.mask = protocol::telemetry_field::kStep | protocol::telemetry_field::kTime | protocol::telemetry_field::kU |
               protocol::telemetry_field::kYTrue;
      s.u()[0] = float((k / 25) % 2);
      s.y_true()[0] = 0.001f * float(k % 50);
      rec.add_sample(id, s);
    }
    rec.end_run(id, "completed", 600, 40);
    rec.flush();
  }
  r = console("train --rig msd --run 3 --db " + shell_quote(db()) + " --out " + shell_quote(dir_.file("g.nlsm")));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "  run 3: 600 samples, 1 gap, ")) << r.output;
}

TEST_F(TrainRuns, TheFitIsKeptInTheFileAndTheUploadedModelKeepsItsHash) {
  record_msd();
  const std::string model = dir_.file("fit.nlsm");
  const auto trained = console("train --rig msd --run 1 --db " + shell_quote(db()) + " --out " + shell_quote(model));
  ASSERT_EQ(trained.code, 0) << trained.output;
  const std::string head = line_of(trained.output, "fit on held-out data of rig msd: the last 1/11 of the run (");
  const std::string row = line_of(trained.output, "  x ");
  ASSERT_FALSE(head.empty()) << trained.output;
  ASSERT_FALSE(row.empty()) << trained.output;
  EXPECT_TRUE(contains(row, " %")) << row;

  const auto info = console("model info " + shell_quote(model));
  ASSERT_EQ(info.code, 0) << info.output;
  EXPECT_EQ(line_of(info.output, "fit on held-out data"), head) << info.output;
  EXPECT_EQ(line_of(info.output, "  x "), row) << info.output;

  std::ifstream in(model, std::ios::binary);
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  ASSERT_GT(bytes.size(), kModelHeaderSize);
  const size_t model_size = model_file_size(bytes[model_offset::kLayers], detail::rd32(&bytes[model_offset::kParams]));
  EXPECT_GT(bytes.size(), model_size) << "no section after the model";
  const uint32_t crc = crc32(bytes.data(), model_size - 4);
  EXPECT_EQ(detail::rd32(&bytes[model_size - 4]), crc);
  char hash[16];
  std::snprintf(hash, sizeof hash, "%08x", crc);
  EXPECT_TRUE(contains(trained.output, "hash 0x" + std::string(hash))) << trained.output;
  EXPECT_TRUE(contains(info.output, "hash 0x" + std::string(hash))) << info.output;

  const std::string script = dir_.file("upload.nls");
  std::ofstream(script) << "model upload " << model << "\nrun 200ms label=after\n";
  const auto session =
      console("--sim msd --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
  ASSERT_EQ(session.code, 0) << session.output;
  EXPECT_TRUE(contains(session.output, "in force: hash " + std::string(hash) + " confirmed")) << session.output;
  EXPECT_EQ(RunStore(db()).run(2).model_hash, crc);

  // Bytes after the model that are no section: not a model file.
  const std::string junk = dir_.file("junk.nlsm");
  std::ofstream(junk, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(model_size))
      << "junk";
  const auto refused = console("model info " + shell_quote(junk));
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_TRUE(contains(refused.output, "'" + junk + "' is not a valid model file: after the model (" +
                                          std::to_string(model_size) + " bytes), the bytes at offset " +
                                          std::to_string(model_size) + " are no section"))
      << refused.output;
  // Cut short inside its fit: the file and the fault named, where the cut is.
  const std::string cut = dir_.file("cut.nlsm");
  std::ofstream(cut, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size() - 10));
  for (const std::string command : {"model info ", "simulate --platform msd --steps 10 --model "}) {
    const auto truncated = console(command + shell_quote(cut));
    EXPECT_EQ(truncated.code, 2) << truncated.output;
    EXPECT_TRUE(contains(truncated.output, cut)) << truncated.output;
    EXPECT_TRUE(contains(truncated.output, "the file ends inside the section at offset " + std::to_string(model_size) +
                                               " (truncated"))
        << truncated.output;
  }
}

}  // namespace
}  // namespace nlsoft::console
