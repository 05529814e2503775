#include "app/record/sqlite.hpp"

#include <fmt/format.h>

#include "app/record/schema_check.hpp"
#include <sys/stat.h>
#include <unistd.h>

namespace nlsoft::console {

std::string db_error_words(const std::string& path, int code, const char* detail) {
  const std::string d = detail ? detail : sqlite3_errstr(code);
  // The console's own queries name only what its schema holds: a missing
  // table or column is a damaged file, or another program's.
  if ((code & 0xFF) == SQLITE_ERROR && d.rfind("no such ", 0) == 0) code = SQLITE_CORRUPT;
  switch (code & 0xFF) {
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      return fmt::format("database {} is locked by another process (another nlsoft-console?): {}", path, d);
    case SQLITE_NOTADB:
    case SQLITE_CORRUPT:
      return fmt::format("database {} is damaged or not an nlsoft database ({}); move it aside or pick another with --db",
                         path, d);
    case SQLITE_READONLY: return fmt::format("database {} is read-only: {}", path, d);
    case SQLITE_FULL: return fmt::format("disk full while writing {}: {}", path, d);
    case SQLITE_CANTOPEN: return fmt::format("cannot open database {}: {}", path, d);
    case SQLITE_TOOBIG:
      return fmt::format("database {} holds a value larger than the {} MiB a recording ever stores ({}); it was not "
                         "written by nlsoft-console: move it aside or pick another with --db",
                         path, kDbMaxValueBytes >> 20, d);
    default: return fmt::format("database {}: {}", path, d);
  }
}

Stmt::Stmt(sqlite3* db, const char* sql) : db_(db) {
  const int rc = sqlite3_prepare_v2(db, sql, -1, &s_, nullptr);
  if (rc != SQLITE_OK) {
    const char* file = sqlite3_db_filename(db, "main");
    throw DbError(db_error_words(file ? file : "?", rc, sqlite3_errmsg(db)), rc);
  }
}

Stmt& Stmt::check(int rc) {
  if (rc != SQLITE_OK) {
    const char* file = sqlite3_db_filename(db_, "main");
    throw DbError(db_error_words(file ? file : "?", rc, sqlite3_errmsg(db_)), rc);
  }
  return *this;
}

bool Stmt::step() {
  const int rc = sqlite3_step(s_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  const char* file = sqlite3_db_filename(db_, "main");
  const std::string msg = db_error_words(file ? file : "?", rc, sqlite3_errmsg(db_));
  sqlite3_reset(s_);
  throw DbError(msg, rc);
}

namespace {

// A path as a URI filename (https://sqlite.org/uri.html): the characters
// that would end or escape the path part are percent-encoded.
std::string uri_of(const std::string& path, const char* query) {
  std::string u = "file:";
  for (char c : path) {
    if (c == '%' || c == '?' || c == '#') u += fmt::format("%{:02X}", static_cast<unsigned char>(c));
    else u += c;
  }
  return u + "?" + query;
}

// Limits and switches for a file that may be anyone's. Triggers stay on
// for a connection that writes: the schema's own (runs_delete_rows) takes a
// deleted run's samples with it, and refuse_foreign_schema() lets no other in.
void harden(sqlite3* db, bool read_only) {
  sqlite3_db_config(db, SQLITE_DBCONFIG_DEFENSIVE, 1, nullptr);
  sqlite3_db_config(db, SQLITE_DBCONFIG_TRUSTED_SCHEMA, 0, nullptr);
  sqlite3_db_config(db, SQLITE_DBCONFIG_ENABLE_VIEW, 0, nullptr);
  sqlite3_db_config(db, SQLITE_DBCONFIG_ENABLE_TRIGGER, read_only ? 0 : 1, nullptr);
  sqlite3_db_config(db, SQLITE_DBCONFIG_ENABLE_LOAD_EXTENSION, 0, nullptr);
  // The largest value a recording stores is a reference's JSON or a note:
  // kilobytes. A bigger one is refused (SQLITE_TOOBIG) instead of read.
  sqlite3_limit(db, SQLITE_LIMIT_LENGTH, kDbMaxValueBytes);
  // The console's own statements are short and shallow; a schema's are
  // checked against ours, but are parsed (and so bounded) first.
  sqlite3_limit(db, SQLITE_LIMIT_SQL_LENGTH, 1 << 20);
  sqlite3_limit(db, SQLITE_LIMIT_EXPR_DEPTH, 100);
  sqlite3_limit(db, SQLITE_LIMIT_COLUMN, 100);
  sqlite3_limit(db, SQLITE_LIMIT_VDBE_OP, 25000);
  sqlite3_limit(db, SQLITE_LIMIT_ATTACHED, 0);
}

bool exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

}  // namespace

Db::Db(const std::string& path, Access access) : path_(path) {
  // SQLite says "disk I/O error" of a folder or a device: said here as what it is.
  if (struct stat st {}; ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw DbError(fmt::format("database {} is {}, not a database file; pick a file with --db", path,
                              S_ISDIR(st.st_mode) ? "a folder" : "not a regular file"),
                  SQLITE_CANTOPEN);
  // Reading a file we may not write (another user's, a read-only folder):
  // SQLite would create -shm/-wal beside it (owned by us, with the file's
  // mode) or fail with "attempt to write a readonly database". mode=ro
  // uses the -shm a writer keeps; with none there, no connection is
  // writing, and immutable=1 reads the file as it is without creating one.
  if (access == Access::ReadOnly && ::access(path.c_str(), W_OK) != 0 && exists(path)) {
    if (exists(path + "-shm")) {
      try {
        open(path, uri_of(path, "mode=ro"), access);
        return;
      } catch (const DbError& e) {
        const int code = e.sqlite_code & 0xFF;
        if (code != SQLITE_CANTOPEN && code != SQLITE_READONLY && code != SQLITE_BUSY) throw;
      }
    }
    open(path, uri_of(path, "immutable=1"), access);
    return;
  }
  open(path, path, access);
}

void Db::open(const std::string& path, const std::string& name, Access access) {
  // Two consoles opening one new file at once: the second's first pragma
  // (journal_mode=WAL, page_size) can meet the first's write lock while it
  // holds a read lock, and SQLite then answers "locked" at once rather than
  // wait (its deadlock rule skips the busy handler). Opening again shortly
  // after sees the finished file; a writer that keeps the file locked still
  // fails after ~1.5 s.
  for (int attempt = 0;; ++attempt) {
    try {
      open_once(path, name, access);
      return;
    } catch (const DbError& e) {
      if ((e.sqlite_code & 0xFF) != SQLITE_BUSY || attempt >= 30) throw;
    }
    ::usleep(50000);
  }
}

void Db::open_once(const std::string& path, const std::string& name, Access access) {
  // Allocation statistics cost a global mutex per malloc; nobody reads them.
  static const int memstatus_off = sqlite3_config(SQLITE_CONFIG_MEMSTATUS, 0);
  (void)memstatus_off;
  const int flags = (access == Access::ReadOnly ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE) |
                    (access == Access::Create ? SQLITE_OPEN_CREATE : 0) | SQLITE_OPEN_NOMUTEX |
                    (name != path ? SQLITE_OPEN_URI : 0);
  int rc = sqlite3_open_v2(name.c_str(), &db_, flags, nullptr);
  if (rc != SQLITE_OK) {
    const std::string msg = db_error_words(path, rc, db_ ? sqlite3_errmsg(db_) : nullptr);
    sqlite3_close(db_);
    db_ = nullptr;
    throw DbError(msg, rc);
  }
  sqlite3_extended_result_codes(db_, 1);
  // A short wait absorbs a reader's checkpoint; a real second writer still
  // fails fast with "locked" instead of hanging the console.
  sqlite3_busy_timeout(db_, 1500);
  // A database is data: a file from anyone (a shared recording, a copy off
  // a stick) may hold views, triggers or huge values meant to run code or
  // eat memory in whoever opens it. SQLite's advice for untrusted files
  // (https://sqlite.org/security.html), before anything reads the schema.
  harden(db_, access == Access::ReadOnly);
  try {
    // Ours or refused, before any pragma writes to it or query reads it.
    refuse_foreign_schema(db_, path);
    // Touching the schema is what reveals a file that is not a database.
    // Big pages suit an append-only log of samples (a no-op on an existing file).
    if (access == Access::ReadOnly) {
      exec("PRAGMA query_only=1");
      exec("SELECT count(*) FROM sqlite_master");  // reads the file (and its WAL) now, not at the first query
    } else {
      exec("PRAGMA page_size=16384");
      exec("PRAGMA journal_mode=WAL");
      exec("PRAGMA synchronous=NORMAL");  // WAL: a crash keeps every commit; power loss may cost the last
    }
    exec("PRAGMA cache_size=-32768");   // 32 MiB: bulk inserts stay in memory until commit
    exec("PRAGMA temp_store=MEMORY");
    exec("PRAGMA foreign_keys=ON");
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

Db::~Db() { sqlite3_close(db_); }

void Db::exec(const char* sql) {
  char* err = nullptr;
  const int rc = sqlite3_exec(db_, sql, nullptr, nullptr, &err);
  if (rc != SQLITE_OK) {
    const std::string msg = db_error_words(path_, rc, err ? err : sqlite3_errmsg(db_));
    sqlite3_free(err);
    throw DbError(msg, rc);
  }
}

}  // namespace nlsoft::console
