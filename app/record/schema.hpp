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

}  // namespace nlsoft::console
