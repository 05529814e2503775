#include "app/record/run_edit.hpp"

#include <fmt/format.h>

#include "app/cli_error.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sample.hpp"
#include "app/record/sqlite.hpp"

namespace nlsoft::console {

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

void delete_run(const std::string& db_path, int64_t id, bool force) {
  RunRow row;
  Db db = open_for_edit(db_path, id, &row);
  if (row.ended_at.empty() && !force)
    throw CliError(fmt::format("run {} is unfinished: a console may still be recording it; nothing deleted "
                               "(--force deletes it anyway, e.g. after a crash)",
                               id));
  try {
    db.exec("BEGIN IMMEDIATE");
    try {
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
      db.exec("COMMIT");
    } catch (...) {
      db.exec("ROLLBACK");
      throw;
    }
  } catch (const DbError& e) {
    throw CliError(fmt::format("run {} not deleted: {}", id, e.what()));
  }
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
