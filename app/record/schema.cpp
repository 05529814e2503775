#include "app/record/schema.hpp"

#include <fmt/format.h>

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
};
static_assert(sizeof(kMigrations) / sizeof(kMigrations[0]) == kSchemaVersion, "one migration per version");

}  // namespace

int schema_version(Db& db) {
  Stmt s = db.prepare("PRAGMA user_version");
  return s.step() ? int(s.int64(0)) : 0;
}

void migrate(Db& db, int target) {
  const int have = schema_version(db);
  if (have > kSchemaVersion)
    throw DbError(fmt::format("database {} has schema v{}, newer than this console's v{}; upgrade nlsoft-console",
                              db.path(), have, kSchemaVersion),
                  SQLITE_ERROR);
  for (int v = have; v < target && v < kSchemaVersion; ++v) {
    db.exec("BEGIN IMMEDIATE");
    try {
      db.exec(kMigrations[v]);
      db.exec(fmt::format("PRAGMA user_version={}", v + 1).c_str());
      db.exec("COMMIT");
    } catch (...) {
      sqlite3_exec(db.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  }
}

}  // namespace nlsoft::console
