#include "app/record/end_words.hpp"

namespace nlsoft::console {

namespace {

bool starts(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }
bool has(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }

// The sentences LiveRuns::run_for writes after "ended early: ".
std::string early_cause(const std::string& why) {
  if (has(why, "watchdog")) return "early: watchdog";
  if (has(why, "telemetry stopped arriving")) return "early: silent";
  if (has(why, "no telemetry arrived")) return "early: no data";
  if (has(why, "left the run")) return "early: fw left";
  if (has(why, "step count did not reach")) return "early: stalled";
  return "early";
}

// A reason no rule knows: its first clause, cut to a column's width.
std::string first_clause(const std::string& s) {
  const size_t cut = s.find_first_of(":;(,");
  std::string w = s.substr(0, cut);
  while (!w.empty() && w.back() == ' ') w.pop_back();
  return w.size() > 18 ? w.substr(0, 17) + "~" : w;
}

}  // namespace

std::string end_words(const std::string& ended_at, const std::string& why) {
  if (ended_at.empty()) return "unfinished";
  if (why == "completed") return "finished";
  if (starts(why, "ended early: ")) return early_cause(why.substr(13));
  if (starts(why, "stopped")) return "stopped";
  if (starts(why, "cancelled")) return "cancelled";
  if (starts(why, "interrupted")) return "interrupted";
  if (starts(why, "console exited")) return "console exit";
  if (starts(why, "recording failed")) return "record failed";
  if (starts(why, "not started")) return "not started";
  if (starts(why, "script error")) return "script error";
  return first_clause(why);
}

std::string failure_words(const std::string& failed) {
  if (starts(failed, "the firmware refused")) return "refused";
  if (starts(failed, "ended early: ")) return early_cause(failed.substr(13));
  if (has(failed, "telemetry frame")) return "lost frames";
  if (starts(failed, "u at a limit")) return "saturated";
  if (has(failed, "objective is not defined")) return "undefined";
  return first_clause(failed);
}

}  // namespace nlsoft::console
