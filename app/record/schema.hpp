#pragma once
// The recording database's schema, versioned with PRAGMA user_version and
// brought up to date by ordered migrations, all in one transaction.
#include "app/record/sqlite.hpp"

namespace nlsoft::console {

constexpr int kSchemaVersion = 7;

// Applies every migration past the file's user_version. Throws DbError for a
// file written by a newer console (it would be misread) or a failed step
// (the transaction rolls back; the file stays at its old version).
void migrate(Db& db, int target = kSchemaVersion);

int schema_version(Db& db);

// The statements that bring a file from version v - 1 to v (1 <= v <=
// kSchemaVersion): what refuse_foreign_schema() builds its reference from.
const char* migration_sql(int v);

}  // namespace nlsoft::console
