// The recording database: schema and migrations, batching, gaps, clear
// errors for locked/corrupt/newer files, and crash safety (a killed writer
// keeps every committed batch and the file passes integrity_check).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "host/files/cli_error.hpp"
#include "app/record/recorder.hpp"
#include "app/record/run_edit.hpp"
#include "app/record/run_metrics.hpp"
#include "app/record/run_store.hpp"
#include "app/record/schema.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

namespace tf = protocol::telemetry_field;
using test::TempDir;

Sample make_sample(uint64_t k, float err = 0.1f) {
  Sample s;
  s.k = k;
  s.step = uint32_t(k);
  s.time_us = uint32_t(k * 1000);
  s.mask = tf::kAll;
  s.n = 3;
  s.m = 2;
  for (int i = 0; i < 3; ++i) {
    s.y_ref()[i] = float(k % 10) + float(i);
    s.y_hat()[i] = s.y_ref()[i] + err / 2;
    s.y_true()[i] = s.y_ref()[i] + err;
  }
  s.u()[0] = 0.25f;
  s.u()[1] = -0.5f;
  s.cost = 1.5f;
  s.iterations = 2;
  s.compute_us = float(k % 100);
  return s;
}

RunInfo run_info(const std::string& label = "t") {
  RunInfo r;
  r.label = label;
  r.platform = "hasel";
  r.firmware = "fake 1.0.0";
  r.loop_rate_hz = 1000;
  r.n = 3;
  r.m = 2;
  r.params = {{"Q", "1 1 1"}, {"N", "3"}};
  return r;
}

int64_t scalar(Db& db, const char* sql) {
  Stmt s = db.prepare(sql);
  return s.step() ? s.int64(0) : -1;
}

TEST(Recorder, FreshDatabaseHasTheCurrentSchema) {
  TempDir dir;
  { Recorder r(dir.file("runs.db")); }
  Db db(dir.file("runs.db"), false);
  EXPECT_EQ(schema_version(db), kSchemaVersion);
  for (const char* t : {"runs", "params", "samples", "gaps", "link_events", "sensor_health"}) {
    Stmt s = db.prepare("SELECT count(*) FROM sqlite_master WHERE type='table' AND name=?");
    s.bind(1, std::string(t));
    ASSERT_TRUE(s.step());
    EXPECT_EQ(s.int64(0), 1) << t;
  }
  Stmt wal = db.prepare("PRAGMA journal_mode");
  ASSERT_TRUE(wal.step());
  EXPECT_EQ(wal.text(0), "wal");
}

TEST(Recorder, MigratesAVersion1DatabaseKeepingItsRuns) {
  TempDir dir;
  const std::string path = dir.file("old.db");
  {
    Db db(path, true);
    migrate(db, 1);
    ASSERT_EQ(schema_version(db), 1);
    db.exec("INSERT INTO runs(started_at,platform,firmware,model_hash,param_hash,loop_rate_hz,n,m,label) "
            "VALUES('2024-01-01T00:00:00Z','msd','old',0,0,1000,1,1,'kept')");
  }
  { Recorder r(path); }
  RunStore store(path);
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].label, "kept");
  EXPECT_EQ(runs[0].samples, 0u);  // the v2 column, defaulted
  Db db(path, false);
  EXPECT_EQ(schema_version(db), kSchemaVersion);
}

TEST(Recorder, RefusesADatabaseFromANewerConsole) {
  TempDir dir;
  const std::string path = dir.file("new.db");
  {
    Db db(path, true);
    db.exec("PRAGMA user_version=99");
  }
  try {
    Recorder r(path);
    FAIL();
  } catch (const DbError& e) {
    EXPECT_NE(std::string(e.what()).find("newer than this console"), std::string::npos) << e.what();
  }
}

TEST(Recorder, NotADatabaseIsAClearErrorAndTheFileIsUntouched) {
  TempDir dir;
  const std::string path = dir.file("junk.db");
  std::ofstream(path) << std::string(4096, 'x');
  try {
    Recorder r(path);
    FAIL();
  } catch (const DbError& e) {
    EXPECT_NE(std::string(e.what()).find("damaged or not an nlsoft database"), std::string::npos) << e.what();
  }
  std::ifstream in(path);
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, std::string(4096, 'x'));
}

TEST(Recorder, LockedDatabaseIsAClearError) {
  TempDir dir;
  const std::string path = dir.file("locked.db");
  { Recorder r(path); }
  Db other(path, false);
  other.exec("BEGIN IMMEDIATE");
  try {
    Recorder r(path);
    FAIL();
  } catch (const DbError& e) {
    EXPECT_NE(std::string(e.what()).find("locked by another process"), std::string::npos) << e.what();
  }
  other.exec("ROLLBACK");
}

TEST(Recorder, BatchesEverySampleIntoItsRun) {
  TempDir dir;
  const std::string path = dir.file("runs.db");
  int64_t id = 0;
  {
    Recorder::Options o;
    o.batch_wakeup = 1000;
    Recorder r(path, o);
    id = r.begin_run(run_info("batch"));
    for (uint64_t k = 0; k < 50000; ++k) ASSERT_TRUE(r.add_sample(id, make_sample(k)));
    r.add_param_change(id, 1.5, "Q", "2 2 2");
    r.add_gap(id, 100, 3, "telemetry frames lost on the link");
    r.end_run(id, "completed", 50000, 3);
    EXPECT_EQ(r.committed_samples(), 50000u);
    EXPECT_EQ(r.dropped_samples(), 0u);
    EXPECT_EQ(r.error(), "");
  }
  RunStore store(path);
  const RunRow row = store.run(id);
  EXPECT_EQ(row.samples, 50000u);
  EXPECT_EQ(row.lost_frames, 3u);
  EXPECT_EQ(row.end_reason, "completed");
  const RunSeries s = store.series(id);
  ASSERT_EQ(s.rows(), 50000u);
  EXPECT_TRUE(s.has_y_true);
  EXPECT_FLOAT_EQ(s.u[1], -0.5f);
  const auto params = store.params(id);
  ASSERT_EQ(params.size(), 3u);
  EXPECT_TRUE(params[0].at_start);
  EXPECT_EQ(params[2].name, "Q");
  EXPECT_EQ(params[2].value, "2 2 2");
  EXPECT_DOUBLE_EQ(params[2].t, 1.5);
  const auto gaps = store.gaps(id);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].after_k, 100u);
  EXPECT_EQ(gaps[0].lost_frames, 3u);

  const RunMetrics m = run_metrics(store, id);
  EXPECT_TRUE(m.has_true);
  ASSERT_EQ(m.truth.rmse.size(), 3u);
  EXPECT_NEAR(m.truth.rmse[0], 0.1, 1e-6);
  EXPECT_NEAR(m.predicted.rmse[2], 0.05, 1e-6);
  EXPECT_NEAR(m.loop_rate_hz, 1000.0, 1e-6);
  EXPECT_EQ(m.lost_frames, 3u);
  EXPECT_EQ(m.gaps, 1u);
  EXPECT_NEAR(*metric_value(m, "compute_p99_us"), 98.0, 1.0);
  EXPECT_EQ(*metric_value(m, "compute_p99"), *metric_value(m, "compute_p99_us")) << "the short spelling reads the same";
}

TEST(Recorder, FullQueueDropsAreRecordedAsAGap) {
  TempDir dir;
  const std::string path = dir.file("runs.db");
  Recorder::Options o;
  o.queue_capacity = 100;
  o.batch_wakeup = 1000000;                // never woken early
  o.batch_delay = std::chrono::hours(1);   // and never by time: only flush
  Recorder r(path, o);
  const int64_t id = r.begin_run(run_info());
  uint64_t accepted = 0;
  for (uint64_t k = 0; k < 150; ++k) accepted += r.add_sample(id, make_sample(k)) ? 1 : 0;
  EXPECT_EQ(accepted, 100u);
  EXPECT_EQ(r.dropped_samples(), 50u);
  r.flush();
  ASSERT_TRUE(r.add_sample(id, make_sample(150)));
  r.end_run(id, "completed", 101, 0);
  RunStore store(path);
  const auto gaps = store.gaps(id);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].lost_frames, 50u);
  EXPECT_EQ(gaps[0].after_k, 99u);
  EXPECT_EQ(gaps[0].reason, "recorder queue full: samples dropped");
}

TEST(Recorder, KilledWriterKeepsEveryCommittedBatch) {
  TempDir dir;
  const std::string path = dir.file("crash.db");
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    close(ready[0]);
    Recorder::Options o;
    o.batch_delay = std::chrono::milliseconds(5);
    Recorder r(path, o);
    const int64_t id = r.begin_run(run_info("crash"));
    uint64_t k = 0;
    for (; k < 20000; ++k) r.add_sample(id, make_sample(k));
    r.flush();
    const char c = 'x';
    if (write(ready[1], &c, 1) != 1) _exit(3);
    for (;; ++k) {  // keep writing until killed mid-batch
      if (!r.add_sample(id, make_sample(k))) usleep(100);
    }
  }
  close(ready[1]);
  char c = 0;
  ASSERT_EQ(read(ready[0], &c, 1), 1);
  usleep(50000);
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));

  Db db(path, false);
  Stmt check = db.prepare("PRAGMA integrity_check");
  ASSERT_TRUE(check.step());
  EXPECT_EQ(check.text(0), "ok");
  const int64_t count = scalar(db, "SELECT count(*) FROM samples");
  const int64_t max_k = scalar(db, "SELECT max(k) FROM samples");
  EXPECT_GE(count, 20000) << "everything flushed before the kill is there";
  EXPECT_EQ(count, max_k + 1) << "committed batches are contiguous: no hole";
  RunStore store(path);
  const RunRow row = store.run(1);
  EXPECT_TRUE(row.ended_at.empty()) << "an unfinished run stays visible as unfinished";
  EXPECT_EQ(row.samples, uint64_t(count));
}


// A colleague's sqlite3 shell holding the write lock for longer than the
// busy timeout stalls the recording, not ends it: the batch is retried and
// every sample lands once the lock is released.
TEST(Recorder, AWriteLockHeldElsewhereDelaysTheRecordingAndLosesNothing) {
  TempDir dir;
  const std::string path = dir.file("busy.db");
  Recorder::Options o;
  o.batch_delay = std::chrono::milliseconds(5);
  Recorder r(path, o);
  const int64_t id = r.begin_run(run_info("busy"));
  Db other(path, false);
  other.exec("BEGIN IMMEDIATE");  // the other process's write lock
  for (uint64_t k = 0; k < 500; ++k) ASSERT_TRUE(r.add_sample(id, make_sample(k)));
  std::thread release([&] {
    // longer than the recorder's busy timeout, so its commit fails at least once
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    other.exec("ROLLBACK");
  });
  r.end_run(id, "completed", 500, 0);  // waits until everything before it is written
  release.join();
  EXPECT_EQ(r.error(), "");
  Db db(path, false);
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM samples"), 500);
  EXPECT_EQ(scalar(db, "SELECT samples FROM runs WHERE id=1"), 500);
}

// A lock held past the busy window: what waited is given up and counted
// lost, so is every sample while the lock lasts (nothing more is held in
// memory), and once it goes the run has one gap saying how many and for how
// long the database was locked, its totals count them lost, and recording
// goes on.
TEST(Recorder, ALockHeldPastTheWindowCountsTheSamplesLostAndRecordsTheGap) {
  TempDir dir;
  const std::string path = dir.file("locked.db");
  Recorder::Options o;
  o.batch_delay = std::chrono::milliseconds(5);
  o.busy_limit = std::chrono::milliseconds(300);
  Recorder r(path, o);
  const int64_t id = r.begin_run(run_info("locked"));
  for (uint64_t k = 0; k < 100; ++k) ASSERT_TRUE(r.add_sample(id, make_sample(k)));
  r.flush();
  Db other(path, false);
  other.exec("BEGIN EXCLUSIVE");
  uint64_t k = 100;
  while (!r.locked_out() && k < 100000) {
    r.add_sample(id, make_sample(k++));
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(r.locked_out()) << "the lock never outlasted the window";
  for (int i = 0; i < 50; ++i) EXPECT_FALSE(r.add_sample(id, make_sample(k++))) << "a sample was held while locked out";
  other.exec("ROLLBACK");
  while (r.locked_out()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(r.add_sample(id, make_sample(k++))) << "recording did not go on";
  r.end_run(id, "completed", k, 0);
  EXPECT_EQ(r.error(), "");
  const uint64_t lost = r.loss(id).samples;
  EXPECT_EQ(lost, k - 110);
  EXPECT_NE(r.loss(id).reason.find("database locked by another process for "), std::string::npos);
  Db db(path, false);
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM samples"), 110);
  EXPECT_EQ(scalar(db, "SELECT samples FROM runs WHERE id=1"), 110);
  EXPECT_EQ(scalar(db, "SELECT lost_frames FROM runs WHERE id=1"), int64_t(lost));
  const auto gaps = RunStore(path).gaps(id);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].after_k, 99u);
  EXPECT_EQ(gaps[0].lost_frames, lost);
  EXPECT_GT(gaps[0].duration_s, 0);
  EXPECT_EQ(gaps[0].reason.rfind("database locked by another process for ", 0), 0u) << gaps[0].reason;
}

// The reading commands open the database read-only (a read-only medium,
// another user's file) and count what a crashed run left in the list too.
TEST(RunStore, ReadsReadOnlyAndListsACrashedRunsSamples) {
  TempDir dir;
  const std::string path = dir.file("ro.db");
  {
    Recorder r(path);
    const int64_t id = r.begin_run(run_info("crashed"));
    for (uint64_t k = 0; k < 300; ++k) r.add_sample(id, make_sample(k));
    r.flush();  // and never end_run: as after a crash
  }
  RunStore store(path);
  EXPECT_TRUE(store.read_only());
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_TRUE(runs[0].ended_at.empty());
  EXPECT_EQ(runs[0].samples, 300u);
}

// `runs delete --force` from another process while this recorder writes
// the run: the recorder stops with an error that says so, instead of going
// on writing samples nobody can see, which the next run given the same id
// would inherit.
TEST(Recorder, ARunDeletedWhileBeingRecordedStopsTheRecordingAndLeavesNoOrphans) {
  TempDir dir;
  const std::string db = dir.file("r.db");
  Recorder rec(db);
  const int64_t id = rec.begin_run(run_info());
  for (uint64_t k = 0; k < 100; ++k) ASSERT_TRUE(rec.add_sample(id, make_sample(k)));
  rec.flush();
  // `runs delete` refuses a run being recorded, --force or not...
  std::string refused;
  try {
    delete_run(db, id, true);
  } catch (const CliError& e) {
    refused = e.what();
  }
  EXPECT_NE(refused.find("run 1 is being recorded by"), std::string::npos) << refused;
  // ...a sqlite3 shell does not ask.
  {
    Db shell(db, false);
    shell.exec("DELETE FROM runs WHERE id=1");
  }
  for (uint64_t k = 100; k < 200; ++k) rec.add_sample(id, make_sample(k));
  std::string error;
  try {
    rec.flush();
  } catch (const DbError& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("run 1 was deleted"), std::string::npos) << error;
  EXPECT_NE(rec.error().find("by another process while it was being recorded"), std::string::npos) << rec.error();
  Db check(db, Db::Access::ReadOnly);
  Stmt c = check.prepare("SELECT count(*) FROM samples");
  ASSERT_TRUE(c.step());
  EXPECT_EQ(c.int64(0), 0) << "orphan samples were written";
}

// A run deleted behind the console's back (a sqlite3 shell) takes its
// samples with it, and its id is never handed out again: the next run starts
// with only its own samples.
TEST(Recorder, RunIdsAreNeverReusedAndADeletedRunsSamplesGoWithIt) {
  TempDir dir;
  const std::string path = dir.file("r.db");
  Recorder rec(path);
  for (int run = 1; run <= 2; ++run) {
    const int64_t id = rec.begin_run(run_info());
    for (uint64_t k = 0; k < 50; ++k) ASSERT_TRUE(rec.add_sample(id, make_sample(k)));
    rec.end_run(id, "completed", 50, 0);
  }
  {
    Db shell(path, false);
    shell.exec("DELETE FROM runs WHERE id=2");
    EXPECT_EQ(scalar(shell, "SELECT count(*) FROM samples WHERE run_id=2"), 0);
  }
  const int64_t next = rec.begin_run(run_info());
  EXPECT_EQ(next, 3);
  ASSERT_TRUE(rec.add_sample(next, make_sample(0)));
  rec.end_run(next, "completed", 1, 0);
  Db db(path, false);
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM samples WHERE run_id=3"), 1);
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM samples"), 51);
}

// Protocol 1.4's SENSOR_HEALTH kept per step (schema v7), and gone with
// its run.
TEST(Recorder, KeepsEachStepsSensorHealthAndDeletesItWithItsRun) {
  TempDir dir;
  const std::string path = dir.file("r.db");
  Recorder rec(path);
  const int64_t id = rec.begin_run(run_info());
  ASSERT_TRUE(rec.add_sample(id, make_sample(0)));
  rec.add_sensor_health(id, 7, 0x38u, 12);
  rec.add_sensor_health(id, 8, 0u, 65535);
  rec.end_run(id, "completed", 1, 0);
  {
    Db db(path, false);
    EXPECT_EQ(scalar(db, "SELECT invalid FROM sensor_health WHERE run_id=1 AND step=7"), 0x38);
    EXPECT_EQ(scalar(db, "SELECT age_ms FROM sensor_health WHERE run_id=1 AND step=7"), 12);
    EXPECT_EQ(scalar(db, "SELECT age_ms FROM sensor_health WHERE run_id=1 AND step=8"), 65535);
    db.exec("DELETE FROM runs WHERE id=1");
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM sensor_health"), 0);
  }
}

// A database of the schema before never-reused ids (v4): migrated in place,
// runs, ids, samples, parameters and gaps kept; rows a deleted run left
// behind are cleared so the next run cannot inherit them.
TEST(Recorder, MigratesAVersion4DatabaseToNeverReusedIdsKeepingItsData) {
  TempDir dir;
  const std::string path = dir.file("v4.db");
  {
    Db db(path, true);
    migrate(db, 4);
    ASSERT_EQ(schema_version(db), 4);
    for (int id : {1, 2})
      db.exec(fmt::format("INSERT INTO runs(id,started_at,ended_at,platform,firmware,model_hash,param_hash,"
                          "loop_rate_hz,n,m,label,samples) VALUES({0},'2024-01-01T00:00:00Z','2024-01-01T00:01:00Z',"
                          "'msd','old',0,0,1000,1,1,'kept{0}',2)",
                          id)
                  .c_str());
    // samples of runs 1 and 2, and of a run 3 deleted by hand long ago
    for (int run : {1, 2, 3})
      for (int k : {0, 1})
        db.exec(fmt::format("INSERT INTO samples(id,step) VALUES({},{})", sample_key(run, uint64_t(k)), k).c_str());
    db.exec("INSERT INTO params(run_id,t,at_start,name,value) VALUES(1,0,1,'Q','1 1 1')");
    db.exec("INSERT INTO gaps(run_id,t,after_k,lost_frames,reason) VALUES(2,'x',0,5,'link down')");
  }
  Recorder rec(path);
  {
    Db db(path, false);
    EXPECT_EQ(schema_version(db), kSchemaVersion);
    Stmt sql = db.prepare("SELECT sql FROM sqlite_master WHERE name='runs'");
    ASSERT_TRUE(sql.step());
    EXPECT_NE(sql.text(0).find("AUTOINCREMENT"), std::string::npos) << sql.text(0);
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM samples WHERE run_id IN (1,2)"), 4);
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM samples WHERE run_id=3"), 0) << "orphans kept";
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM params WHERE run_id=1"), 1) << "the rebuild cascaded to params";
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM gaps WHERE run_id=2"), 1);
  }
  const auto runs = RunStore(path).list();
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].label, "kept1");
  EXPECT_EQ(runs[1].id, 2);
  EXPECT_FALSE(runs[1].ended_at.empty());
  const int64_t next = rec.begin_run(run_info());
  EXPECT_EQ(next, 3);
  rec.end_run(next, "completed", 0, 0);
  Db db(path, false);
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM samples WHERE run_id=3"), 0);
}

}  // namespace
}  // namespace nlsoft::console
