#include "app/record/schema_check.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cctype>
#include <map>
#include <mutex>
#include <tuple>
#include <vector>

#include "app/record/schema.hpp"
#include "app/record/sqlite.hpp"
#include "host/files/printable.hpp"

namespace nlsoft::console {

using host::printable_excerpt;

namespace {

// type and name -> the statement that made it, normalised.
using Schema = std::map<std::pair<std::string, std::string>, std::string>;

// The statement as SQLite keeps it, with runs of white space as one space
// and identifier quotes dropped: another SQLite version may quote a renamed
// table ("runs") where this one does not, and that is no other schema.
std::string normalised(const std::string& sql) {
  std::string out;
  bool space = false;
  for (auto c = sql.begin(); c != sql.end(); ++c) {
    if (std::isspace(static_cast<unsigned char>(*c))) {
      space = true;
      continue;
    }
    if (*c == '"') continue;
    if (space && !out.empty()) out += ' ';
    space = false;
    out += *c;
  }
  return out;
}

Schema read_schema(sqlite3* db, int* rc) {
  Schema out;
  sqlite3_stmt* s = nullptr;
  *rc = sqlite3_prepare_v2(db, "SELECT type, name, sql FROM sqlite_master", -1, &s, nullptr);
  while (*rc == SQLITE_OK) {
    *rc = sqlite3_step(s);
    if (*rc != SQLITE_ROW) break;
    *rc = SQLITE_OK;
    auto text = [&](int col) {
      const unsigned char* t = sqlite3_column_text(s, col);
      return t ? std::string(reinterpret_cast<const char*>(t), size_t(sqlite3_column_bytes(s, col))) : std::string();
    };
    const std::string type = text(0), name = text(1);
    // SQLite's own statistics (ANALYZE, run by hand): read by the planner only.
    if (type == "table" && (name == "sqlite_stat1" || name == "sqlite_stat4")) continue;
    out[{type, name}] = normalised(text(2));
  }
  if (*rc == SQLITE_DONE) *rc = SQLITE_OK;
  sqlite3_finalize(s);
  return out;
}

// Schema v (0..kSchemaVersion) as the migrations make it, built once in
// memory by this very SQLite.
const Schema& reference_schema(int v) {
  static std::array<Schema, kSchemaVersion + 1> schemas;
  static std::once_flag built;
  std::call_once(built, [] {
    sqlite3* mem = nullptr;
    sqlite3_open(":memory:", &mem);
    int rc = SQLITE_OK;
    for (int i = 0; i <= kSchemaVersion; ++i) {
      if (i > 0) rc = sqlite3_exec(mem, migration_sql(i), nullptr, nullptr, nullptr);
      if (rc == SQLITE_OK) schemas[size_t(i)] = read_schema(mem, &rc);
      // The migrations are this program's own text: a failure is a bug in it.
      if (rc != SQLITE_OK) {
        std::fprintf(stderr, "nlsoft: schema v%d does not build: %s\n", i, sqlite3_errmsg(mem));
        std::abort();
      }
    }
    sqlite3_close(mem);
  });
  return schemas[size_t(v)];
}

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw DbError(fmt::format("database {} is not an nlsoft recording database: {}; the console reads a recording as "
                            "data and runs nothing a file brings, so move it aside or pick another with --db",
                            path, why),
                SQLITE_NOTADB);
}

}  // namespace

void refuse_foreign_schema(sqlite3* db, const std::string& path) {
  // The version and the schema from one snapshot: a console creating the
  // file meanwhile commits both or neither between them.
  int rc = sqlite3_exec(db, "BEGIN", nullptr, nullptr, nullptr);
  sqlite3_stmt* s = nullptr;
  if (rc == SQLITE_OK) rc = sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &s, nullptr);
  int version = 0;
  if (rc == SQLITE_OK && (rc = sqlite3_step(s)) == SQLITE_ROW) version = sqlite3_column_int(s, 0), rc = SQLITE_OK;
  sqlite3_finalize(s);
  Schema have;
  if (rc == SQLITE_OK) have = read_schema(db, &rc);
  const std::string why = rc == SQLITE_OK ? "" : sqlite3_errmsg(db);
  if (sqlite3_get_autocommit(db) == 0) sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr);
  if (rc != SQLITE_OK) throw DbError(db_error_words(path, rc, why.c_str()), rc);
  if (version > kSchemaVersion)
    throw DbError(fmt::format("database {} has schema v{}, newer than this console's v{}; upgrade nlsoft-console",
                              path, version, kSchemaVersion),
                  SQLITE_ERROR);
  if (version < 0) refuse(path, fmt::format("its schema version is {}", version));
  const Schema& ours = reference_schema(version);
  // What would run is named first: a view, a trigger, then the rest.
  std::vector<std::pair<std::pair<std::string, std::string>, std::string>> order;
  for (const char* type : {"view", "trigger", ""})
    for (const auto& entry : have)
      if (*type ? entry.first.first == type : entry.first.first != "view" && entry.first.first != "trigger")
        order.push_back(entry);
  for (const auto& [key, sql] : order) {
    const auto it = ours.find(key);
    if (it == ours.end())
      refuse(path, fmt::format("it holds a {} named '{}' that schema v{} does not define", key.first,
                               printable_excerpt(key.second, 40), version));
    if (it->second != sql)
      refuse(path, fmt::format("its {} '{}' is not the one schema v{} defines", key.first,
                               printable_excerpt(key.second, 40), version));
  }
  for (const auto& [key, sql] : ours)
    if (!have.count(key))
      refuse(path, fmt::format("it lacks the {} '{}' that schema v{} defines", key.first, key.second, version));
}

}  // namespace nlsoft::console
