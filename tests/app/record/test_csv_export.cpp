// CSV export: header names every column, floats round-trip exactly, missing
// fields are empty cells, t is the step time, and a failed export leaves no
// file behind.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/files/cli_error.hpp"
#include "host/files/output_file.hpp"
#include "app/record/csv_export.hpp"
#include "app/record/recorder.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {

using host::CliError;
using host::OutputFile;

namespace {

namespace tf = protocol::telemetry_field;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

TEST(CsvExport, RoundTripsEveryRecordedValue) {
  test::TempDir dir;
  const std::string db = dir.file("runs.db");
  int64_t id = 0;
  std::vector<Sample> written;
  {
    Recorder r(db);
    RunInfo info;
    info.platform = "tendon";
    info.firmware = "fake";
    info.n = 3;
    info.m = 2;
    id = r.begin_run(info);
    for (uint64_t k = 0; k < 100; ++k) {
      Sample s;
      s.k = k;
      s.n = 3;
      s.m = 2;
      s.mask = k == 5 ? uint8_t(tf::kStep | tf::kYRef) : tf::kAll;  // one sparse row
      s.step = uint32_t(2 * k);
      s.time_us = uint32_t(k * 8333);
      for (int i = 0; i < 3; ++i) {
        s.y_ref()[i] = 1.0f / float(k + 3 + i);
        s.y_hat()[i] = -1e-7f * float(k + i);
        s.y_true()[i] = 3.14159265f * float(i + 1) + float(k);
      }
      s.u()[0] = 0.1f;
      s.u()[1] = -1.2f;
      s.cost = 1e6f / float(k + 1);
      s.iterations = 3;
      s.compute_us = 12.5f;
      r.add_sample(id, s);
      written.push_back(s);
    }
    r.end_run(id, "completed", 100, 0);
  }
  RunStore store(db);
  const std::string csv = dir.file("run.csv");
  EXPECT_EQ(export_run_csv(store, id, csv), 100u);
  std::ifstream in(csv);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line,
            "k,step,time_us,y_ref0,y_ref1,y_ref2,y_hat0,y_hat1,y_hat2,y_true0,y_true1,y_true2,u0,u1,cost,iterations,"
            "compute_us,t");
  size_t rows = 0;
  while (std::getline(in, line)) {
    const auto c = split(line);
    ASSERT_EQ(c.size(), 18u) << line;
    EXPECT_EQ(c[17], "") << "the run recorded no loop rate: its steps have no time";
    const Sample& s = written[rows];
    EXPECT_EQ(std::stoull(c[0]), s.k);
    EXPECT_EQ(std::stoul(c[1]), s.step);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(std::strtof(c[size_t(3 + i)].c_str(), nullptr), s.y_ref()[i]);
    if (rows == 5) {
      EXPECT_EQ(c[2], "");
      EXPECT_EQ(c[9], "");
      EXPECT_EQ(c[16], "");
    } else {
      for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(std::strtof(c[size_t(6 + i)].c_str(), nullptr), s.y_hat()[i]);
        EXPECT_EQ(std::strtof(c[size_t(9 + i)].c_str(), nullptr), s.y_true()[i]);
      }
      EXPECT_EQ(std::strtof(c[13].c_str(), nullptr), -1.2f);
      EXPECT_EQ(std::strtof(c[14].c_str(), nullptr), s.cost);
      EXPECT_EQ(c[15], "3");
    }
    ++rows;
  }
  EXPECT_EQ(rows, 100u);
}

// The step time: (step - the run's first step) / the run's loop rate, the
// very double, whatever the firmware's clock said (a --sim-fast simulator's
// time_us is the host's: 34 us per step of a 130 Hz run here). A row without
// a step has an empty t; each run of several counts from its own first step.
TEST(CsvExport, TIsTheStepCountOverTheLoopRateNotTheFirmwareClock) {
  test::TempDir dir;
  const std::string db = dir.file("runs.db");
  std::vector<int64_t> ids;
  {
    Recorder r(db);
    for (uint32_t first : {100u, 7u}) {
      RunInfo info;
      info.platform = "hasel";
      info.n = 3;
      info.m = 6;
      info.loop_rate_hz = 130;
      const int64_t id = r.begin_run(info);
      for (uint64_t k = 0; k < 50; ++k) {
        Sample s;
        s.k = k;
        s.n = 3;
        s.m = 6;
        s.mask = k == 20 ? uint8_t(tf::kTime | tf::kU) : uint8_t(tf::kStep | tf::kTime | tf::kU);
        s.step = first + uint32_t(k);
        s.time_us = uint32_t(5000 + 34 * k);
        r.add_sample(id, s);
      }
      r.end_run(id, "completed", 50, 0);
      ids.push_back(id);
    }
  }
  RunStore store(db);
  // t_col: the last column's index (3 + 3n + m + 3, one more with a run column).
  auto check = [&](const std::string& csv, size_t t_col, size_t runs) {
    const size_t rows_each = 50;
    std::ifstream in(csv);
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line.substr(line.rfind(',')), ",t") << line;
    EXPECT_EQ(split(line).size(), t_col + 1) << line;
    size_t row = 0;
    while (std::getline(in, line)) {
      const auto c = split(line);
      ASSERT_EQ(c.size(), t_col + 1) << line;
      const size_t k = row % rows_each;
      if (k == 20) {
        EXPECT_EQ(c[t_col], "") << line;
      } else {
        EXPECT_EQ(std::strtod(c[t_col].c_str(), nullptr), double(k) / 130.0) << line;
      }
      ++row;
    }
    EXPECT_EQ(row, rows_each * runs);
  };
  const std::string one = dir.file("one.csv");
  ASSERT_EQ(export_run_csv(store, ids[0], one), 50u);
  check(one, 3 + 3 * 3 + 6 + 3, 1);
  // The first rows by hand: t = 0, 1/130, 2/130, and time_us as sent.
  {
    std::ifstream in(one);
    std::string line;
    std::getline(in, line);
    for (int k = 0; k < 3; ++k) {
      std::getline(in, line);
      const auto c = split(line);
      EXPECT_EQ(c[1], std::to_string(100 + k));
      EXPECT_EQ(c[2], std::to_string(5000 + 34 * k));
      EXPECT_EQ(std::strtod(c.back().c_str(), nullptr), double(k) / 130.0);
    }
  }
  const std::string both = dir.file("both.csv");
  ASSERT_EQ(export_runs_csv(store, ids, both), 100u);
  check(both, 1 + 3 + 3 * 3 + 6 + 3, 2);
}

TEST(CsvExport, UnwritablePathIsAClearErrorAndNoFileIsLeft) {
  test::TempDir dir;
  const std::string db = dir.file("runs.db");
  int64_t id = 0;
  {
    Recorder r(db);
    RunInfo info;
    info.platform = "msd";
    info.n = 1;
    info.m = 1;
    id = r.begin_run(info);
    r.end_run(id, "completed", 0, 0);
  }
  RunStore store(db);
  try {
    export_run_csv(store, id, dir.file("no/such/dir/out.csv"));
    FAIL();
  } catch (const CliError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write"), std::string::npos) << e.what();
  }
  try {
    export_run_csv(store, 42, dir.file("out.csv"));
    FAIL();
  } catch (const CliError& e) {
    EXPECT_STREQ(e.what(), "no run 42 (runs are numbered 1..1; see `nlsoft-console runs list`)");
  }
  std::ifstream probe(dir.file("out.csv"));
  EXPECT_FALSE(probe.good());
}

// Where an export goes: a symlink to a device (/dev/stdout) stays a symlink
// and gets the bytes, "-" is standard output, a regular file is replaced
// whole, and nothing is left beside it.
TEST(OutputFile, DevicesAreWrittenInPlaceFilesReplacedWholeAndDashIsStdout) {
  test::TempDir dir;
  const std::string link = dir.file("to-null");
  ASSERT_EQ(::symlink("/dev/null", link.c_str()), 0);
  {
    OutputFile f(link);
    std::fputs("discarded\n", f.get());
    f.commit();
  }
  char target[64] = {};
  ASSERT_GT(::readlink(link.c_str(), target, sizeof target - 1), 0) << "the symlink was replaced";
  EXPECT_STREQ(target, "/dev/null");

  const std::string file = dir.file("out.csv");
  { std::ofstream(file) << "old\n"; }
  {
    OutputFile f(file);
    std::fputs("new\n", f.get());
    // not committed: the old file stays, no temporary is left
  }
  std::string line;
  std::getline(std::ifstream(file), line);
  EXPECT_EQ(line, "old");
  {
    OutputFile f(file);
    std::fputs("new\n", f.get());
    f.commit();
  }
  std::getline(std::ifstream(file), line);
  EXPECT_EQ(line, "new");
  size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path)) entries += e.path().filename() != "to-null";
  EXPECT_EQ(entries, 1u) << "a temporary was left beside the file";

  testing::internal::CaptureStdout();
  {
    OutputFile f("-");
    std::fputs("to stdout\n", f.get());
    f.commit();
  }
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "to stdout\n");
}

}  // namespace
}  // namespace nlsoft::console
