#include "app/tui/exit_summary.hpp"

#include <fmt/format.h>

#include "app/record/run_store.hpp"

namespace nlsoft::console::tui {

namespace {

// A path as a shell reads it back: quoted when it holds anything but the
// characters paths usually have.
std::string shell_word(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_./-+,:=@%") ==
                        std::string::npos)
    return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

std::string exit_summary(LiveConsole& console) {
  const std::vector<int64_t> ids = console.runs().session_runs();
  const std::string db = shell_word(console.db_path());
  if (!console.recording())
    return ids.empty() ? "nlsoft-console: no run this session (--no-record: nothing was kept)\n"
                       : fmt::format("nlsoft-console: {} run{} this session, not kept (--no-record)\n", ids.size(),
                                     ids.size() == 1 ? "" : "s");
  if (ids.empty())
    return fmt::format("nlsoft-console: no run recorded this session; earlier runs: nlsoft-console runs list --db {}\n",
                       db);
  std::string out = fmt::format("nlsoft-console: {} run{} recorded this session in {}\n", ids.size(),
                                ids.size() == 1 ? "" : "s", console.db_path());
  for (const int64_t id : ids) {
    try {
      const RunMetrics m = console.runs().metrics(id);
      const RunRow row = RunStore(console.db_path()).run(id);
      // The time the run lasted; a run the console could not close has
      // only the time its samples span.
      const double s = m.wall_s > 0 ? m.wall_s : m.duration_s;
      out += fmt::format("  run {}  {:.1f} s  {} samples{}{}\n", id, s, m.samples,
                         row.label.empty() ? "" : "  " + row.label, row.ended_at.empty() ? "  (unfinished)" : "");
    } catch (const std::exception& e) {
      out += fmt::format("  run {}  ({})\n", id, e.what());
    }
  }
  out += fmt::format("see one: nlsoft-console runs show {} --db {}\n", ids.back(), db);
  return out;
}

}  // namespace nlsoft::console::tui
