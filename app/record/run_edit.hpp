#pragma once
// The two writes `runs` makes to a recording after the fact: delete a run
// (its samples, parameters, gaps and link events with it) and relabel one.
// Each is one transaction: it happens whole or not at all.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nlsoft::console {

// A run's label: one line of a listing, not a document. Longer ones are
// refused (CliError) rather than cut, so nothing typed is silently lost.
constexpr size_t kMaxLabelChars = 200;
void check_label(const std::string& label);

// Throws CliError: no such run; a run a console is recording (its liveness
// mark, recorder_mark.hpp, is fresh), even with `force`; an unfinished run
// whose recorder is gone unless `force`; a locked or read-only database.
// Returns what the caller should say: for each run whose recorder was found
// gone (killed), that it was and why it is thought so.
std::vector<std::string> delete_run(const std::string& db_path, int64_t id, bool force);
// Several runs in one transaction: each is checked as above first, then all
// are deleted or none.
std::vector<std::string> delete_runs(const std::string& db_path, const std::vector<int64_t>& ids, bool force);

// Throws CliError as above (a label may change on an unfinished run).
void label_run(const std::string& db_path, int64_t id, const std::string& label);

}  // namespace nlsoft::console
