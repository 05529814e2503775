#include "app/record/tune_log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "host/files/cli_error.hpp"
#include "app/gnuplot_text.hpp"
#include "app/record/row_columns.hpp"
#include "app/record/utc_time.hpp"

namespace nlsoft::console {

using host::CliError;

TuneLog::TuneLog(const std::string& db_path) : db_(std::make_unique<Db>(db_path, Db::Access::ReadWrite)) {}
TuneLog::~TuneLog() = default;

int64_t TuneLog::begin(const std::string& objective, const std::string& space, const std::string& method) {
  Stmt s = db_->prepare("INSERT INTO tune_sessions(started_at, objective, space, method) VALUES(?,?,?,?)");
  s.bind(1, utc_now()).bind(2, objective).bind(3, space).bind(4, method);
  s.step();
  return db_->last_insert_id();
}

void TuneLog::add(const TuneEvalRow& e) {
  Stmt s = db_->prepare("INSERT INTO tune_evals(run_id, session_id, eval, objective, failed, point) VALUES(?,?,?,?,?,?)");
  s.bind(1, e.run_id).bind(2, e.session_id).bind(3, int64_t(e.eval));
  if (e.objective && std::isfinite(*e.objective)) s.bind(4, *e.objective);
  else s.bind_null(4);
  s.bind(5, e.failed).bind(6, e.point);
  s.step();
}

void TuneLog::finish(int64_t session, const std::string& reason, int64_t best_run) {
  Stmt s = db_->prepare("UPDATE tune_sessions SET ended_at=?, end_reason=?, best_run=? WHERE id=?");
  s.bind(1, utc_now()).bind(2, reason);
  if (best_run > 0) s.bind(3, best_run);
  else s.bind_null(3);
  s.bind(4, session);
  s.step();
}

namespace {

bool has_tables(Db& db) {
  Stmt s = db.prepare("SELECT count(*) FROM sqlite_master WHERE type='table' AND name='tune_sessions'");
  return s.step() && s.int64(0) > 0;
}

const Column<TuneSessionRow> kSessionColumns[] = {
    {"id", read_field<&TuneSessionRow::id>},
    {"started_at", read_field<&TuneSessionRow::started_at>},
    {"ifnull(ended_at,'')", read_field<&TuneSessionRow::ended_at>},
    {"objective", read_field<&TuneSessionRow::objective>},
    {"space", read_field<&TuneSessionRow::space>},
    {"method", read_field<&TuneSessionRow::method>},
    {"ifnull(end_reason,'')", read_field<&TuneSessionRow::end_reason>},
    {"ifnull(best_run,0)", read_field<&TuneSessionRow::best_run>},
};

const Column<TuneEvalRow> kEvalColumns[] = {
    {"run_id", read_field<&TuneEvalRow::run_id>},
    {"session_id", read_field<&TuneEvalRow::session_id>},
    {"eval", read_field<&TuneEvalRow::eval>},
    {"objective", read_field<&TuneEvalRow::objective>},  // NULL: the evaluation failed
    {"failed", read_field<&TuneEvalRow::failed>},
    {"point", read_field<&TuneEvalRow::point>},
};

}  // namespace

std::vector<TuneSessionRow> tune_sessions(const std::string& db_path) {
  Db db(db_path, Db::Access::ReadOnly);
  std::vector<TuneSessionRow> out;
  if (!has_tables(db)) return out;
  Stmt s = db.prepare(fmt::format("SELECT {} FROM tune_sessions ORDER BY id", select_list(kSessionColumns)).c_str());
  while (s.step()) out.push_back(read_row(s, kSessionColumns));
  return out;
}

TuneSessionRow tune_session(const std::string& db_path, int64_t id) {
  Db db(db_path, Db::Access::ReadOnly);
  if (has_tables(db)) {
    Stmt s = db.prepare(fmt::format("SELECT {} FROM tune_sessions WHERE id=?", select_list(kSessionColumns)).c_str());
    s.bind(1, id);
    if (s.step()) return read_row(s, kSessionColumns);
  }
  throw CliError(fmt::format("no tuning session {} in {} (runs list shows them)", id, db_path));
}

std::vector<TuneEvalRow> tune_evals(const std::string& db_path, int64_t session) {
  Db db(db_path, Db::Access::ReadOnly);
  std::vector<TuneEvalRow> out;
  if (!has_tables(db)) return out;
  Stmt s = db.prepare(
      fmt::format("SELECT {} FROM tune_evals WHERE session_id=? ORDER BY eval", select_list(kEvalColumns)).c_str());
  s.bind(1, session);
  while (s.step()) out.push_back(read_row(s, kEvalColumns));
  return out;
}

std::string tune_plot_script(const TuneSessionRow& session, const std::vector<TuneEvalRow>& evals, ImageFormat format) {
  if (evals.empty()) throw CliError(fmt::format("tuning session {} has no evaluations to plot", session.id));
  std::string s = "# nlsoft-console runs plot --tune\n";
  s += format == ImageFormat::Svg
           ? "set terminal svg size 900,500 noenhanced font \"sans,10\" background \"white\"\n"
           : "set terminal pngcairo size 900,500 noenhanced font \"sans,9\" background \"white\"\n";
  s += "set encoding utf8\nset grid\nset key outside right top\nset datafile missing NaN\n";
  // A log axis reads a convergence best when every value is positive.
  double lo = INFINITY;
  bool any_ok = false;
  for (const auto& e : evals)
    if (e.objective) lo = std::min(lo, *e.objective), any_ok = true;
  const bool log_axis = any_ok && lo > 0;
  double best = INFINITY;
  s += "$evals << EOD\n";
  for (const auto& e : evals) {
    if (e.objective) best = std::min(best, *e.objective);
    s += fmt::format("{} {} {} {}\n", e.eval, e.objective ? fmt::format("{:.8g}", *e.objective) : "NaN",
                     std::isfinite(best) ? fmt::format("{:.8g}", best) : "NaN", e.objective ? "NaN" : "0");
  }
  s += "EOD\n";
  std::string title = fmt::format("tuning session {}: minimise {}  over  {}  ({}, {} evaluations", session.id,
                                  session.objective, session.space, session.method, evals.size());
  if (any_ok) title += fmt::format(", best {:.5g}", best);
  title += ")";
  s += fmt::format("set title {}\nset xlabel \"evaluation\"\nset ylabel \"objective\"\n", gnuplot_string(title));
  if (log_axis) s += "set logscale y\n";
  // Failed evaluations sit on the bottom edge: they scored nothing.
  s += fmt::format("set xrange [0:{}]\n", evals.back().eval + 1);
  s += fmt::format(
      "plot $evals using 1:2 with points pt 7 ps 0.8 lc rgb \"#1f77b4\" title \"objective\", \\\n"
      "     $evals using 1:3 with steps lw 1.5 lc rgb \"#d62728\" title \"best so far\", \\\n"
      "     $evals using 1:($4 == 0 ? {:.8g} : NaN) with points pt 2 ps 1.2 lc rgb \"#000000\" title \"failed\"\n",
      any_ok ? lo : 0.0);
  return s;
}

}  // namespace nlsoft::console
