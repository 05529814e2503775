#include "app/record/run_edit.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "host/files/cli_error.hpp"
#include "app/record/recorder_mark.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sample.hpp"
#include "app/record/sqlite.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

// Checks the id against what is recorded (RunStore's "no run N" message),
// then opens the file for writing.
Db open_for_edit(const std::string& db_path, int64_t id, RunRow* row) {
  {
    RunStore store(db_path);
    *row = store.run(id);
  }
  try {
    return Db(db_path, Db::Access::ReadWrite);
  } catch (const DbError& e) {
    throw CliError(e.what());
  }
}

}  // namespace

void check_label(const std::string& label) {
  size_t chars = 0;
  for (char c : label) chars += (static_cast<unsigned char>(c) & 0xc0) != 0x80;
  if (chars > kMaxLabelChars)
    throw CliError(fmt::format("a label is at most {} characters; this one has {} (put longer text in the run's notes)",
                               kMaxLabelChars, chars));
}

std::vector<std::string> delete_run(const std::string& db_path, int64_t id, bool force) {
  return delete_runs(db_path, {id}, force);
}

namespace {

RecorderMark mark_of(Db& db, int64_t id) {
  Stmt s = db.prepare("SELECT ifnull(recorder_pid,0), ifnull(recorder_host,''), ifnull(heartbeat_at,0) FROM runs WHERE id=?");
  s.bind(1, id);
  RecorderMark m;
  if (s.step()) m = RecorderMark{s.int64(0), s.text(1), s.real(2)};
  return m;
}

}  // namespace

std::vector<std::string> delete_runs(const std::string& db_path, const std::vector<int64_t>& ids, bool force) {
  if (ids.empty()) throw CliError("runs delete: give at least one run id");
  // Every id is checked before anything is deleted: all of them go, or none.
  RunRow row;
  Db db = open_for_edit(db_path, ids.front(), &row);
  std::vector<bool> unfinished;
  for (int64_t id : ids) {
    row = RunStore(db_path).run(id);
    unfinished.push_back(row.ended_at.empty());
  }
  const std::string list = fmt::format("{}", fmt::join(ids, ", "));
  std::vector<std::string> notes;
  try {
    db.exec("BEGIN IMMEDIATE");
    try {
      // The recorders' marks are read under the write lock: a console that
      // is recording renews its mark every second, and cannot begin or end
      // a run between this check and the delete.
      const double now = unix_now();
      for (size_t i = 0; i < ids.size(); ++i) {
        if (!unfinished[i]) continue;
        const MarkVerdict v = judge_mark(mark_of(db, ids[i]), now);
        if (v.state == MarkVerdict::Live)
          throw CliError(fmt::format("run {} is being recorded by {}; stop that run first; nothing deleted", ids[i],
                                     v.holder));
        if (!force)
          throw CliError(fmt::format("run {} is unfinished: {}; nothing deleted (--force deletes it anyway, e.g. after a "
                                     "crash)",
                                     ids[i],
                                     v.state == MarkVerdict::Stale
                                         ? fmt::format("its recorder, {}, left it so: {}", v.holder, v.why)
                                         : std::string("a console may still be recording it")));
        if (v.state == MarkVerdict::Stale)
          notes.push_back(fmt::format("run {}: its recorder, {}, left it unfinished: {}; deleting it", ids[i],
                                      v.holder, v.why));
      }
      for (int64_t id : ids) {
        Stmt s = db.prepare("DELETE FROM samples WHERE id BETWEEN ? AND ?");
        s.bind(1, sample_key(id, 0)).bind(2, sample_key(id, 0xFFFFFFFFu));
        s.step();
        for (const char* sql : {"DELETE FROM params WHERE run_id=?", "DELETE FROM gaps WHERE run_id=?",
                                "DELETE FROM link_events WHERE run_id=?", "DELETE FROM tune_evals WHERE run_id=?",
                                "DELETE FROM runs WHERE id=?"}) {
          Stmt d = db.prepare(sql);
          d.bind(1, id);
          d.step();
        }
      }
      db.exec("COMMIT");
    } catch (...) {
      sqlite3_exec(db.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  } catch (const DbError& e) {
    throw CliError(fmt::format("{} {} not deleted: {}", ids.size() == 1 ? "run" : "runs", list, e.what()));
  }
  return notes;
}

void label_run(const std::string& db_path, int64_t id, const std::string& label) {
  check_label(label);
  RunRow row;
  Db db = open_for_edit(db_path, id, &row);
  try {
    Stmt s = db.prepare("UPDATE runs SET label=? WHERE id=?");
    s.bind(1, label).bind(2, id);
    s.step();
  } catch (const DbError& e) {
    throw CliError(fmt::format("run {} not relabelled: {}", id, e.what()));
  }
}

}  // namespace nlsoft::console
