#pragma once
// Tuning sessions in the recording database: which runs were evaluations of
// which session, in what order, what each scored. Written while tuning,
// read by `runs list` (grouping) and `runs plot --tune` (convergence).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/record/run_plot.hpp"
#include "app/record/sqlite.hpp"

namespace nlsoft::console {

struct TuneSessionRow {
  int64_t id = 0;
  std::string started_at, ended_at, objective, space, method, end_reason;
  int64_t best_run = 0;  // 0: no evaluation succeeded
};

struct TuneEvalRow {
  int64_t run_id = 0, session_id = 0;
  int eval = 0;
  std::optional<double> objective;  // empty: failed
  std::string failed;               // why, when it failed
  std::string point;                // "Lambda=0.5 Q*=12"
};

// One connection of its own: a handful of rows per session, next to the
// recorder's stream of samples (WAL lets both write in turn).
class TuneLog {
 public:
  explicit TuneLog(const std::string& db_path);
  ~TuneLog();
  int64_t begin(const std::string& objective, const std::string& space, const std::string& method);
  void add(const TuneEvalRow& e);
  void finish(int64_t session, const std::string& reason, int64_t best_run);

 private:
  std::unique_ptr<Db> db_;
};

// Reading; an older file without the tables has no sessions. Throw
// CliError for an unknown session.
std::vector<TuneSessionRow> tune_sessions(const std::string& db_path);
TuneSessionRow tune_session(const std::string& db_path, int64_t id);
std::vector<TuneEvalRow> tune_evals(const std::string& db_path, int64_t session);

// The gnuplot script of a session's convergence: the objective per
// evaluation, the best so far, failed evaluations marked on the axis.
std::string tune_plot_script(const TuneSessionRow& s, const std::vector<TuneEvalRow>& evals, ImageFormat format);

}  // namespace nlsoft::console
