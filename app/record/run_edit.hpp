#pragma once
// The two writes `runs` makes to a recording after the fact: delete a run
// (its samples, parameters, gaps and link events with it) and relabel one.
// Each is one transaction: it happens whole or not at all.
#include <cstdint>
#include <string>

namespace nlsoft::console {

// Throws CliError: no such run; an unfinished run (a console may still be
// recording it) unless `force`; a locked or read-only database.
void delete_run(const std::string& db_path, int64_t id, bool force);

// Throws CliError as above (a label may change on an unfinished run).
void label_run(const std::string& db_path, int64_t id, const std::string& label);

}  // namespace nlsoft::console
