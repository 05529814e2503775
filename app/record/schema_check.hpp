#pragma once
// A recording database is data, not code: a file from anyone (a shared
// recording, a copy off a stick) is opened only if every table, index,
// view and trigger in it is one this console's schema defines, word for
// word. A view named `runs` would run its query, a trigger of its own would
// run on `runs label`; neither is ever executed, the file is refused first.
#include <sqlite3.h>

#include <string>

namespace nlsoft::console {

// Throws DbError, one sentence naming `path` and the first foreign or
// missing object; also for a schema newer than this console's (it cannot
// be checked, and would be misread).
void refuse_foreign_schema(sqlite3* db, const std::string& path);

}  // namespace nlsoft::console
