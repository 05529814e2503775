// A recording database is data from anyone: a file shared, copied or made
// by hand to hurt whoever opens it. Each crafted file here is opened by the
// real console's readers (runs list, show, export), which must end with one
// sentence naming the file (and the run), never crash, loop or run code the
// file brings: counts that overrun the sample's arrays (n = 255 copied 1020
// bytes into a 60-float array), blobs of the wrong size, a view named runs,
// a trigger of the file's own, a value of many megabytes.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <stdlib.h>

#include <string>

#include "app/record/recorder.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;

using test::run_process;
using test::shell_quote;

class CraftedDb : public ::testing::Test {
 protected:
  // One finished run of 20 samples, n = 1, m = 1, as the console records it.
  void SetUp() override {
    Recorder rec(db());
    RunInfo ri;
    ri.platform = "msd";
    ri.n = 1;
    ri.m = 1;
    const int64_t id = rec.begin_run(ri);
    for (uint64_t k = 0; k < 20; ++k) {
      Sample s;
      s.k = k;
      s.n = 1;
      s.m = 1;
      s.step = uint32_t(k);
      s.mask = protocol::telemetry_field::kStep | protocol::telemetry_field::kYRef | protocol::telemetry_field::kYHat |
               protocol::telemetry_field::kU;
      s.y_ref()[0] = 1.0f;
      s.y_hat()[0] = 0.5f;
      s.u()[0] = 0.25f;
      rec.add_sample(id, s);
    }
    rec.end_run(id, "completed", 20, 0);
  }
  // What someone with the sqlite3 shell does to the file.
  void craft(const std::string& sql) const {
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(db().c_str(), &h), SQLITE_OK);
    char* err = nullptr;
    const int rc = sqlite3_exec(h, sql.c_str(), nullptr, nullptr, &err);
    const std::string why = err ? err : "";
    sqlite3_free(err);
    sqlite3_close(h);
    ASSERT_EQ(rc, SQLITE_OK) << why;
  }
  int64_t count(const std::string& sql) const {
    sqlite3* h = nullptr;
    sqlite3_open(db().c_str(), &h);
    sqlite3_stmt* s = nullptr;
    sqlite3_prepare_v2(h, sql.c_str(), -1, &s, nullptr);
    const int64_t n = sqlite3_step(s) == SQLITE_ROW ? sqlite3_column_int64(s, 0) : -1;
    sqlite3_finalize(s);
    sqlite3_close(h);
    return n;
  }
  test::ProcessResult runs(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " runs " + args + " --db " + shell_quote(db()));
  }
  // Refused as an error (not a crash: -1 is a signal), in one line naming
  // the file and `what`.
  void expect_refused(const std::string& args, const std::string& what) const {
    const auto r = runs(args);
    EXPECT_NE(r.code, 0) << args << ": " << r.output;
    EXPECT_NE(r.code, -1) << args << ": killed by a signal: " << r.output;
    EXPECT_TRUE(contains(r.output, db())) << args << ": " << r.output;
    EXPECT_TRUE(contains(r.output, what)) << args << ": " << r.output;
    std::string rest = r.output;
    while (!rest.empty() && rest.back() == '\n') rest.pop_back();
    EXPECT_EQ(rest.find('\n'), std::string::npos) << args << ": one sentence: " << r.output;
  }
  void expect_every_reader_refuses(const std::string& what) const {
    expect_refused("list", what);
    expect_refused("show 1", what);
    expect_refused("export 1 --csv " + shell_quote(dir_.file("out.csv")), what);
  }
  std::string db() const { return dir_.file("runs.db"); }
  test::TempDir dir_;
};

TEST_F(CraftedDb, TheRecordedFileIsReadByEveryReader) {
  EXPECT_EQ(runs("list").code, 0);
  EXPECT_EQ(runs("show 1").code, 0);
  const auto r = runs("export 1 --csv " + shell_quote(dir_.file("out.csv")));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "20 samples")) << r.output;
}

// The file: every reader crashed (gdb: returned into the blob).
TEST_F(CraftedDb, ACountPastTheSamplesRoomIsRefusedNamingTheRun) {
  craft("UPDATE runs SET n=255; UPDATE samples SET y_ref=randomblob(1020);");
  expect_every_reader_refuses("run 1 is damaged or not written by nlsoft-console: n (outputs) = 255, where a run has 0 to 15");
}

// n = 16 wrote past the array without crashing: refused all the same.
TEST_F(CraftedDb, OneOutputTooManyIsRefusedToo) {
  craft("UPDATE runs SET n=16; UPDATE samples SET y_ref=randomblob(64), y_hat=randomblob(64);");
  expect_every_reader_refuses("n (outputs) = 16");
  craft("UPDATE runs SET n=1, m=-1;");
  expect_refused("show 1", "m (inputs) = -1");
  craft("UPDATE runs SET m=4294967297;");  // 2^32 + 1: read as 1 by a plain cast
  expect_refused("show 1", "m (inputs) = -1");
  craft("UPDATE runs SET m=1, w=59;");
  expect_refused("show 1", "w (sensors) = 59, where a run has 0 to 58");
}

TEST_F(CraftedDb, ABlobNotTheSizeTheRunSaysIsRefusedNamingTheSample) {
  craft("UPDATE samples SET u=randomblob(8) WHERE k=7;");
  expect_every_reader_refuses("run 1 is damaged or not written by nlsoft-console: sample 7 holds 8 bytes of u, where m = 1 makes 4");
}

// A runs table that is a view ran its query: a recursive one never ended.
TEST_F(CraftedDb, AViewIsRefusedNotRun) {
  craft("ALTER TABLE runs RENAME TO runs_kept; "
        "CREATE VIEW runs AS WITH RECURSIVE c(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM c) "
        "SELECT i AS id, '' AS started_at, '' AS ended_at, '' AS label, '' AS notes, '' AS platform, '' AS firmware, "
        "'' AS reference, '' AS end_reason, 0 AS model_hash, 0 AS param_hash, 0 AS loop_rate_hz, 1 AS n, 1 AS m, "
        "1 AS decimation, 0 AS samples, 0 AS lost_frames, 'control' AS kind, 0 AS w, '' AS excitation FROM c;");
  expect_every_reader_refuses("is not an nlsoft recording database: it holds a view named 'runs'");
}

// The file's own trigger deleted every sample on `runs label`.
TEST_F(CraftedDb, ATriggerOfTheFilesOwnIsRefusedAndNeverFires) {
  craft("CREATE TRIGGER wipe AFTER UPDATE ON runs BEGIN DELETE FROM samples; END;");
  expect_every_reader_refuses("it holds a trigger named 'wipe'");
  const auto r = runs("label 1 kept");
  EXPECT_NE(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "it holds a trigger named 'wipe'")) << r.output;
  EXPECT_EQ(count("SELECT count(*) FROM samples"), 20);
  // The schema's own trigger changed is no longer ours either.
  craft("DROP TRIGGER wipe; DROP TRIGGER runs_delete_rows; "
        "CREATE TRIGGER runs_delete_rows AFTER DELETE ON runs BEGIN DELETE FROM samples; END;");
  expect_refused("list", "its trigger 'runs_delete_rows' is not the one schema v7 defines");
}

// A value of 17 MiB is no recording's: refused before it is read whole.
TEST_F(CraftedDb, AnOversizedValueIsRefused) {
  craft("UPDATE runs SET notes=zeroblob(17 * 1048576);");
  expect_every_reader_refuses("holds a value larger than the 16 MiB a recording ever stores");
}

// runs list printed the file's start time and rig raw (runs show escaped them).
TEST_F(CraftedDb, RunsListShowsTheFilesTextEscaped) {
  craft("UPDATE runs SET started_at='2026' || char(27) || '[2J' || char(155) || 'x', "
        "platform='ms' || char(27) || ']0;t' || char(7) || char(8238);");
  const auto r = runs("list");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "2026\\x1b[2J")) << r.output;
  EXPECT_TRUE(contains(r.output, "ms\\x1b]0;t\\x07")) << r.output;
  EXPECT_FALSE(contains(r.output, "\x1b")) << r.output;
  EXPECT_FALSE(contains(r.output, "\xc2\x9b")) << r.output;
  EXPECT_FALSE(contains(r.output, "\xe2\x80\xae")) << r.output;
}

}  // namespace
}  // namespace nlsoft::console
