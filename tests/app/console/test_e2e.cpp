// End to end over a pty: nlsoft-console --sim runs nlsoft-firmware-sim and
// executes scripts headless; the recording is then checked in the database.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/link/sim_launcher.hpp"
#include "app/live/reference_table.hpp"
#include "app/record/run_store.hpp"
#include "run_process.hpp"
#include "shared/plant_hasel.hpp"
#include "temp_dir.hpp"

namespace nlsoft::console {
namespace {

using test::run_process;
using test::shell_quote;

class ConsoleE2E : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }

  test::ProcessResult run_script(const std::string& text, const std::string& platform = "hasel",
                                 const std::string& extra = "") {
    script_ = dir_.file("tune.nls");
    std::ofstream(script_) << text;
    return run_process(fmt_command(platform, extra));
  }
  std::string fmt_command(const std::string& platform, const std::string& extra) const {
    return std::string(NLSOFT_CONSOLE_BIN) + " --sim " + platform + " --db " + shell_quote(db()) + " --script " +
           shell_quote(script_) + " " + extra;
  }
  std::string db() const { return dir_.file("runs.db"); }

  test::TempDir dir_;
  std::string script_;
};

TEST_F(ConsoleE2E, SetParametersUploadSwirlRunAndCheckTheRecording) {
  const std::string csv = dir_.file("swirl.csv");
  write_reference_csv(swirl_table(HaselPlant::kSwirlCentre, HaselPlant::kSwirlScale, 3), csv);
  const auto r = run_script(
      "# the tuning session of the issue, headless\n"
      "set Q 1e6 2e6 1e6\n"
      "set Lambda 1 1 1 1 1 1\n"
      "get Q\n"
      "ref load " + csv + " hold=1\n"
      "run 3s label=swirl-e2e\n"
      "note swirl from a CSV table, paper tuning\n"
      "expect lost == 0\n"
      "expect samples >= 380\n"
      "export csv " + dir_.file("run.csv") + "\n");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("Q = 1e+06 2e+06 1e+06"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("uploaded and selected"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("ok: lost = 0 == 0"), std::string::npos) << r.output;

  RunStore store(db());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  const RunRow& run = runs[0];
  EXPECT_EQ(run.label, "swirl-e2e");
  EXPECT_EQ(run.notes, "swirl from a CSV table, paper tuning");
  EXPECT_EQ(run.platform, "hasel");
  EXPECT_EQ(run.end_reason, "completed");
  EXPECT_EQ(run.lost_frames, 0u);
  EXPECT_NE(run.reference.find("\"kind\":\"table\""), std::string::npos) << run.reference;
  const RunSeries s = store.series(run.id);
  EXPECT_GE(s.rows(), 380u);
  EXPECT_EQ(s.rows(), run.samples);
  EXPECT_TRUE(s.has_y_true);
  // Steps are consecutive (decimation 1) and the reference is the table's
  // first points: the Swirl rests at its centre for 30 points.
  for (size_t i = 1; i < s.rows(); ++i) ASSERT_EQ(s.step[i], s.step[i - 1] + 1) << "at sample " << i;
  EXPECT_EQ(s.step[0], 0u);
  EXPECT_FLOAT_EQ(s.y_ref[0], HaselPlant::kSwirlCentre[0]);
  bool q_at_start = false;
  for (const auto& p : store.params(run.id)) q_at_start |= p.at_start && p.name == "Q" && p.value == "1e+06 2e+06 1e+06";
  EXPECT_TRUE(q_at_start);
  std::ifstream exported(dir_.file("run.csv"));
  size_t lines = 0;
  for (std::string l; std::getline(exported, l);) ++lines;
  EXPECT_EQ(lines, s.rows() + 1);
}

TEST_F(ConsoleE2E, FailedExpectExitsOneWithFileAndLine) {
  const auto r = run_script("ref hold\nrun 500ms\nexpect samples > 1e9\nexpect lost == 0\n", "msd");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("tune.nls:3: expect samples > 1e+09 failed: samples = "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("ok: lost = 0 == 0"), std::string::npos) << r.output;
}

TEST_F(ConsoleE2E, RefusedParameterExitsTwoAndChangesNothing) {
  const auto r = run_script("get Q\nset Q[1] -5\n", "hasel");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("tune.nls:2: Q[1] = -5 is out of range [0, 1e+12]"), std::string::npos) << r.output;
  const auto after = run_script("get Q\n", "hasel");
  EXPECT_EQ(after.code, 0) << after.output;
  EXPECT_NE(after.output.find("Q = 1e+06 2e+06 1e+06"), std::string::npos) << after.output;
}

TEST_F(ConsoleE2E, ScriptErrorIsReportedBeforeConnecting) {
  const auto r = run_script("set Q 1 2 3\nrun ten seconds\n");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("tune.nls:2: 'ten' is not a duration"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("connected:"), std::string::npos) << r.output;
}

TEST_F(ConsoleE2E, ParamsSaveLoadShowsTheDiff) {
  const std::string saved = dir_.file("p.params");
  const auto r = run_script("params save " + saved + "\nset Q 5 5 5\nparams load " + saved + "\nget Q\n");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("Q: 5 5 5 -> 1e+06 2e+06 1e+06"), std::string::npos) << r.output;
}

TEST_F(ConsoleE2E, SweepPrintsATablePerSetting) {
  const auto r = run_script("ref hold\nsweep Q0 1 1000 run 300ms\n", "msd");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("Q0  run"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Q restored to 1"), std::string::npos) << r.output;
}

// Rows are comparable: each starts the reference over with the actuators
// neutral and is measured after a stated settling time, which the table says.
TEST_F(ConsoleE2E, SweepRowsSettleBeforeTheyAreMeasured) {
  const auto r = run_script("ref steps\nsweep Q0 1 1000 run 300ms settle=200ms\n", "msd");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("each row: the reference restarted from its first point, actuators from neutral; measured "
                          "over 0.3 s after 0.2 s to settle"),
            std::string::npos)
      << r.output;
  RunStore store(db());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 2u);
  for (const RunRow& run : runs) {
    EXPECT_GE(run.samples, 500u) << "settle + measured time recorded";
    // The table's samples column counts only the measured part (~300 at 1 kHz).
    long measured = -1;
    std::istringstream lines(r.output);
    for (std::string line; std::getline(lines, line);) {
      std::istringstream words(line);
      std::string value, id, samples;
      if (words >> value >> id >> samples && id == std::to_string(run.id)) measured = std::atol(samples.c_str());
    }
    EXPECT_GT(measured, 250) << r.output;
    EXPECT_LT(measured, 400) << r.output;
  }
  EXPECT_NE(run_script("sweep Q0 1 2 run 1s settle=soon\n", "msd").output.find("'soon' is not a duration"),
            std::string::npos);
}

// Disk full, as a file-size limit makes it: the shell's `ulimit -f` only,
// as a user would set it (the console itself must keep SIGXFSZ from killing
// it, so the write fails with EFBIG): the recording fails a second or so
// into a ten-minute run, and the console stops the run at once and says so,
// exit 2, instead of dying without a word (exit 153) or running on
// unrecorded. `timeout` turns waiting out the run into a failure here.
TEST_F(ConsoleE2E, ADiskFullStopsTheRunAtOnce) {
  script_ = dir_.file("full.nls");
  std::ofstream(script_) << "run 600s label=full\n";
  const auto r = run_process("ulimit -f 600; exec timeout 80 " + fmt_command("msd", "--sim-rate 5000"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("stopped at once: recording failed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("samples received"), std::string::npos) << r.output;
}

// The same on the HASEL rig at its own rate, a minute's run under a smaller
// limit: the run is not left unfinished by a killed console.
TEST_F(ConsoleE2E, AFileSizeLimitDuringARunIsReportedNotFatal) {
  script_ = dir_.file("r60.nls");
  std::ofstream(script_) << "run 60s label=r60\n";
  // dash counts 512-byte blocks: 800 is bash's `ulimit -f 400`.
  const auto r = run_process("ulimit -f 800; exec timeout 80 " + fmt_command("hasel", ""));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("run 1 stopped at once: recording failed"), std::string::npos) << r.output;
}

// The simulator's log lives in a folder of the console's own (0700), not at
// a predictable /tmp name another user could plant a link at, and goes away
// with the launcher.
TEST_F(ConsoleE2E, SimulatorLogIsPrivateAndRemoved) {
  std::string dir;
  {
    nlsoft::console::SimLauncher sim;
    const std::string pty = sim.start("msd");
    ASSERT_FALSE(pty.empty());
    dir = std::filesystem::path(sim.log_path()).parent_path().string();
    EXPECT_EQ(dir.rfind("/tmp/nlsoft-sim.", 0), 0u) << dir;
    struct stat st {};
    ASSERT_EQ(::stat(dir.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0700u);
    ASSERT_EQ(::lstat(sim.log_path().c_str(), &st), 0);
    EXPECT_TRUE(S_ISREG(st.st_mode));
  }
  EXPECT_FALSE(std::filesystem::exists(dir));
}

}  // namespace
}  // namespace nlsoft::console
