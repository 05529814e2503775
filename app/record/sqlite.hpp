#pragma once
// Thin RAII over the SQLite C API: a connection, prepared statements, and
// errors that carry the file name and SQLite's own message. No ORM: the
// recorder's statements are few and hot.
#include <sqlite3.h>

#include <cstdint>
#include <stdexcept>
#include <string>

namespace nlsoft::console {

// The largest text or blob a connection reads or writes: a recording's
// largest values (a reference's JSON, notes) are kilobytes.
constexpr int kDbMaxValueBytes = 16 << 20;

struct DbError : std::runtime_error {
  DbError(const std::string& what, int code) : std::runtime_error(what), sqlite_code(code) {}
  int sqlite_code;
};

class Stmt {
 public:
  Stmt() = default;
  Stmt(sqlite3* db, const char* sql);
  ~Stmt() { sqlite3_finalize(s_); }
  Stmt(Stmt&& o) noexcept : s_(o.s_), db_(o.db_) { o.s_ = nullptr; }
  Stmt& operator=(Stmt&& o) noexcept {
    std::swap(s_, o.s_);
    std::swap(db_, o.db_);
    return *this;
  }
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;

  Stmt& bind(int i, int64_t v) { return check(sqlite3_bind_int64(s_, i, v)); }
  Stmt& bind(int i, double v) { return check(sqlite3_bind_double(s_, i, v)); }
  Stmt& bind(int i, const std::string& v) {
    return check(sqlite3_bind_text(s_, i, v.data(), int(v.size()), SQLITE_TRANSIENT));
  }
  // The blob must stay alive until step(): the hot path binds in place.
  Stmt& bind_blob(int i, const void* p, size_t n) { return check(sqlite3_bind_blob(s_, i, p, int(n), SQLITE_STATIC)); }
  Stmt& bind_null(int i) { return check(sqlite3_bind_null(s_, i)); }

  // True while a row is available; false when done. Throws on error.
  bool step();
  void exec() {
    while (step()) {
    }
    reset();
  }
  void reset() {
    sqlite3_reset(s_);
    sqlite3_clear_bindings(s_);
  }
  // For a statement whose every parameter is bound again before each step.
  void reset_keep_bindings() { sqlite3_reset(s_); }

  int64_t int64(int col) const { return sqlite3_column_int64(s_, col); }
  double real(int col) const { return sqlite3_column_double(s_, col); }
  bool is_null(int col) const { return sqlite3_column_type(s_, col) == SQLITE_NULL; }
  std::string text(int col) const {
    const unsigned char* t = sqlite3_column_text(s_, col);
    return t ? std::string(reinterpret_cast<const char*>(t), size_t(sqlite3_column_bytes(s_, col))) : std::string();
  }
  const void* blob(int col, size_t& n) const {
    const void* p = sqlite3_column_blob(s_, col);
    n = size_t(sqlite3_column_bytes(s_, col));
    return p;
  }

 private:
  Stmt& check(int rc);
  sqlite3_stmt* s_ = nullptr;
  sqlite3* db_ = nullptr;
};

class Db {
 public:
  // Opens (creating if asked) and applies the recorder's pragmas; read-only
  // for the commands that only read (runs list|show|export|compare), so a
  // database on a read-only medium or another user's file serves them.
  // Throws DbError in words: locked by another process, not a database, ...
  enum class Access { Create, ReadWrite, ReadOnly };
  Db(const std::string& path, Access access);
  Db(const std::string& path, bool create) : Db(path, create ? Access::Create : Access::ReadWrite) {}
  ~Db();
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;

  void exec(const char* sql);
  Stmt prepare(const char* sql) { return Stmt(db_, sql); }
  sqlite3* handle() { return db_; }
  const std::string& path() const { return path_; }
  int64_t last_insert_id() const { return sqlite3_last_insert_rowid(db_); }

 private:
  void open(const std::string& path, const std::string& name, Access access);  // name: a path or a URI
  void open_once(const std::string& path, const std::string& name, Access access);
  sqlite3* db_ = nullptr;
  std::string path_;
};

// The message for a failed SQLite call on `path`, with advice for the
// common cases (locked, corrupt, read-only, disk full).
std::string db_error_words(const std::string& path, int code, const char* detail);

}  // namespace nlsoft::console
