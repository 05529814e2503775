#include "app/record/schema.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace nlsoft::console {

namespace {

// Append only: a released migration never changes, or databases created by
// it would differ from ones migrated through it.
const char* const kMigrations[] = {
    // v1: runs, parameters, samples, gaps, link events.
    R"sql(
CREATE TABLE runs(
  id INTEGER PRIMARY KEY,
  started_at TEXT NOT NULL,            -- UTC, ISO 8601
  ended_at TEXT,                       -- NULL while running or after a crash
  label TEXT NOT NULL DEFAULT '',
  notes TEXT NOT NULL DEFAULT '',
  platform TEXT NOT NULL,
  firmware TEXT NOT NULL,              -- name and version from INFO
  model_hash INTEGER NOT NULL,
  param_hash INTEGER NOT NULL,
  loop_rate_hz REAL NOT NULL,          -- nominal, from INFO
  n INTEGER NOT NULL,
  m INTEGER NOT NULL,
  decimation INTEGER NOT NULL DEFAULT 1,
  reference TEXT NOT NULL DEFAULT '',  -- JSON
  end_reason TEXT
);
CREATE TABLE params(
  run_id INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
  t REAL NOT NULL,                     -- seconds since the run started (0 at start)
  at_start INTEGER NOT NULL,           -- 1: value in force when the run started
  name TEXT NOT NULL,
  value TEXT NOT NULL                  -- space-separated, as the console prints it
);
CREATE INDEX params_run ON params(run_id);
-- One row per telemetry frame. Vectors are little-endian f32 blobs (n or m
-- values); a missing field is NULL. The key is run_id << 32 | k so a run's
-- samples are one contiguous rowid range and inserts always append (the
-- fastest path SQLite has: no second index to maintain).
CREATE TABLE samples(
  id INTEGER PRIMARY KEY,              -- run_id * 4294967296 + k
  step INTEGER,
  time_us INTEGER,
  y_ref BLOB, y_hat BLOB, y_true BLOB, u BLOB,
  cost REAL,
  iterations INTEGER,
  compute_us REAL,
  -- Derived, stored nowhere: free on insert, handy in ad-hoc SQL.
  run_id INTEGER GENERATED ALWAYS AS (id >> 32) VIRTUAL,
  k INTEGER GENERATED ALWAYS AS (id & 4294967295) VIRTUAL  -- 0, 1, ... in arrival order
);
CREATE TABLE gaps(
  run_id INTEGER NOT NULL,
  t TEXT NOT NULL,
  after_k INTEGER NOT NULL,            -- the gap lies between samples k and k+1
  lost_frames INTEGER NOT NULL,
  reason TEXT NOT NULL
);
CREATE TABLE link_events(
  id INTEGER PRIMARY KEY,
  t TEXT NOT NULL,
  run_id INTEGER,
  kind TEXT NOT NULL,
  detail TEXT NOT NULL
);
)sql",
    // v2: per-run totals kept with the run, so listing runs needs no scan.
    R"sql(
ALTER TABLE runs ADD COLUMN samples INTEGER NOT NULL DEFAULT 0;
ALTER TABLE runs ADD COLUMN lost_frames INTEGER NOT NULL DEFAULT 0;
CREATE INDEX gaps_run ON gaps(run_id);
)sql",
    // v3: how long a gap lasted, so an outage reads as time, not only as
    // frames (NULL: not known, as for gaps recorded before v3).
    R"sql(
ALTER TABLE gaps ADD COLUMN duration_s REAL;
)sql",
    // v4: tuning sessions. Each evaluation is an ordinary run; these rows
    // say which session it belongs to, in which order, and what it scored,
    // so the session can be listed and plotted without re-deriving the
    // objective.
    R"sql(
CREATE TABLE tune_sessions(
  id INTEGER PRIMARY KEY,
  started_at TEXT NOT NULL,            -- UTC, ISO 8601
  ended_at TEXT,                       -- NULL while tuning or after a crash
  objective TEXT NOT NULL,             -- the expression minimised
  space TEXT NOT NULL,                 -- the searched parameters, as given
  method TEXT NOT NULL,                -- the NLopt algorithm
  end_reason TEXT,
  best_run INTEGER                     -- NULL until one evaluation succeeded
);
CREATE TABLE tune_evals(
  run_id INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL,
  eval INTEGER NOT NULL,               -- 1, 2, ... in the order they ran
  objective REAL,                      -- NULL: the evaluation failed
  failed TEXT NOT NULL DEFAULT '',     -- why it scored as failed
  point TEXT NOT NULL                  -- the candidate, NAME=VALUE ...
);
CREATE INDEX tune_evals_session ON tune_evals(session_id);
)sql",
    // v5: run ids are never used twice (AUTOINCREMENT: a deleted run's id
    // once went to the next run, with whatever of its rows were left); a
    // run's rows go with it however it is deleted (a trigger: samples are
    // keyed by id range, which no foreign key can express); and a liveness
    // mark the recording console keeps, so `runs delete` can tell a run
    // being recorded from one a killed console left unfinished. SQLite
    // cannot add AUTOINCREMENT to a table: it is rebuilt, rows and ids kept
    // (migrate() turns foreign keys off around it, or dropping the old
    // table would cascade to params).
    R"sql(
CREATE TABLE runs_v5(
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  started_at TEXT NOT NULL,
  ended_at TEXT,
  label TEXT NOT NULL DEFAULT '',
  notes TEXT NOT NULL DEFAULT '',
  platform TEXT NOT NULL,
  firmware TEXT NOT NULL,
  model_hash INTEGER NOT NULL,
  param_hash INTEGER NOT NULL,
  loop_rate_hz REAL NOT NULL,
  n INTEGER NOT NULL,
  m INTEGER NOT NULL,
  decimation INTEGER NOT NULL DEFAULT 1,
  reference TEXT NOT NULL DEFAULT '',
  end_reason TEXT,
  samples INTEGER NOT NULL DEFAULT 0,
  lost_frames INTEGER NOT NULL DEFAULT 0,
  recorder_pid INTEGER,                -- the recording console's, while it records (NULL once ended)
  recorder_host TEXT,                  -- where that PID lives
  heartbeat_at REAL                    -- Unix time, renewed every second while recording
);
INSERT INTO runs_v5(id,started_at,ended_at,label,notes,platform,firmware,model_hash,param_hash,loop_rate_hz,n,m,
                    decimation,reference,end_reason,samples,lost_frames)
  SELECT id,started_at,ended_at,label,notes,platform,firmware,model_hash,param_hash,loop_rate_hz,n,m,
         decimation,reference,end_reason,samples,lost_frames FROM runs;
DROP TABLE runs;
ALTER TABLE runs_v5 RENAME TO runs;
-- What deleted runs left behind would be inherited by nobody now, but it
-- is dead weight: gone with the rebuild.
DELETE FROM samples WHERE run_id NOT IN (SELECT id FROM runs);
DELETE FROM params WHERE run_id NOT IN (SELECT id FROM runs);
DELETE FROM gaps WHERE run_id NOT IN (SELECT id FROM runs);
DELETE FROM link_events WHERE run_id IS NOT NULL AND run_id NOT IN (SELECT id FROM runs);
DELETE FROM tune_evals WHERE run_id NOT IN (SELECT id FROM runs);
CREATE TRIGGER runs_delete_rows AFTER DELETE ON runs BEGIN
  DELETE FROM samples WHERE id BETWEEN old.id * 4294967296 AND old.id * 4294967296 + 4294967295;
  DELETE FROM gaps WHERE run_id = old.id;
  DELETE FROM link_events WHERE run_id = old.id;
  DELETE FROM tune_evals WHERE run_id = old.id;
END;
)sql",
    // v6: identification runs (`ident`): open loop, the firmware's
    // excitation on the inputs. A run says which kind it is and, for an
    // identification run, the signal it ran; its samples keep the sensors
    // (l, w floats) beside u and the measured y (in y_true), what a model
    // is trained from.
    R"sql(
ALTER TABLE runs ADD COLUMN kind TEXT NOT NULL DEFAULT 'control';  -- 'control' | 'ident'
ALTER TABLE runs ADD COLUMN w INTEGER NOT NULL DEFAULT 0;          -- sensors per sample in samples.l
ALTER TABLE runs ADD COLUMN excitation TEXT NOT NULL DEFAULT '';   -- JSON: signal, seed, amplitude, band, duration
ALTER TABLE samples ADD COLUMN l BLOB;                             -- w little-endian f32, NULL when not recorded
)sql",
    // v7: the health of sensor channels read from chips (protocol 1.4
    // SENSOR_HEALTH): per step of a run whose rig has chips, which channels
    // held no valid sample and how old the samples were. A table of its
    // own, joined on (run_id, step): rigs without chips add no column to
    // every sample, and a step whose health was lost has no row.
    R"sql(
CREATE TABLE sensor_health(
  run_id INTEGER NOT NULL,
  step INTEGER NOT NULL,
  invalid INTEGER NOT NULL,            -- bit i: sensor channel i invalid at this step
  age_ms INTEGER NOT NULL              -- the oldest valid chip sample's age (65535: that or older)
);
CREATE INDEX sensor_health_run ON sensor_health(run_id, step);
DROP TRIGGER runs_delete_rows;
CREATE TRIGGER runs_delete_rows AFTER DELETE ON runs BEGIN
  DELETE FROM samples WHERE id BETWEEN old.id * 4294967296 AND old.id * 4294967296 + 4294967295;
  DELETE FROM gaps WHERE run_id = old.id;
  DELETE FROM link_events WHERE run_id = old.id;
  DELETE FROM tune_evals WHERE run_id = old.id;
  DELETE FROM sensor_health WHERE run_id = old.id;
END;
)sql",
};
static_assert(sizeof(kMigrations) / sizeof(kMigrations[0]) == kSchemaVersion, "one migration per version");

}  // namespace

const char* migration_sql(int v) { return v >= 1 && v <= kSchemaVersion ? kMigrations[v - 1] : ""; }

int schema_version(Db& db) {
  Stmt s = db.prepare("PRAGMA user_version");
  return s.step() ? int(s.int64(0)) : 0;
}

namespace {

void refuse_newer(Db& db, int have) {
  if (have > kSchemaVersion)
    throw DbError(fmt::format("database {} has schema v{}, newer than this console's v{}; upgrade nlsoft-console",
                              db.path(), have, kSchemaVersion),
                  SQLITE_ERROR);
}

}  // namespace

void migrate(Db& db, int target) {
  int have = schema_version(db);
  refuse_newer(db, have);
  if (have >= target) return;
  // A table rebuilt by a migration is dropped and replaced: with foreign
  // keys on, the drop would delete the rows that refer to it (the pragma is
  // a no-op inside a transaction, so it goes around them).
  db.exec("PRAGMA foreign_keys=OFF");
  try {
    // One transaction for every step: the file moves from its version to
    // the target whole or not at all, and a page several steps rewrite (a
    // new file's) goes into the WAL once, not once a step.
    db.exec("BEGIN IMMEDIATE");
    try {
      // Two consoles started together on a file not there yet both read
      // version 0 above; the one that waited for the write lock finds the
      // other's tables made: the version that counts is the one read under
      // the lock.
      have = schema_version(db);
      refuse_newer(db, have);
      for (int v = have; v < target && v < kSchemaVersion; ++v) db.exec(kMigrations[v]);
      if (have < target) db.exec(fmt::format("PRAGMA user_version={}", std::min(target, kSchemaVersion)).c_str());
      db.exec("COMMIT");
    } catch (...) {
      sqlite3_exec(db.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  } catch (...) {
    sqlite3_exec(db.handle(), "PRAGMA foreign_keys=ON", nullptr, nullptr, nullptr);
    throw;
  }
  db.exec("PRAGMA foreign_keys=ON");
}

}  // namespace nlsoft::console
