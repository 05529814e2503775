#include "app/record/merge_y.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "host/files/cli_error.hpp"
#include "app/record/capture_csv.hpp"
#include "app/record/capture_offset.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sample.hpp"
#include "app/record/sqlite.hpp"

namespace nlsoft::console {

using host::CliError;

namespace tf = protocol::telemetry_field;

namespace {

// 12010 -> "12,010": counts a reader compares at a glance.
std::string grouped(size_t v) {
  std::string s = std::to_string(v);
  for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(size_t(i), ",");
  return s;
}

}  // namespace

MergeReport merge_y(const std::string& db_path, int64_t run_id, const std::string& csv_path,
                    std::optional<double> offset_s, const std::vector<std::string>& names) {
  if (offset_s && !std::isfinite(*offset_s)) throw CliError("--offset: give a finite number of seconds");
  RunSignals run;
  std::vector<int64_t> keys;
  int n = 0;
  {
    RunStore store(db_path);
    const RunRow row = store.run(run_id);
    if (row.ended_at.empty())
      throw CliError(fmt::format("run {} is unfinished (being recorded, or left so by a crash): merge a capture into a "
                                 "finished run",
                                 run_id));
    if (!(row.loop_rate_hz > 0)) throw CliError(fmt::format("run {} has no loop rate: its samples have no time", run_id));
    if (row.n <= 0) throw CliError(fmt::format("run {} has no outputs (n = 0): nothing to merge", run_id));
    n = row.n;
    run.m = row.m;
    run.w = row.w;
    bool no_step = false;
    uint32_t step0 = 0;
    store.for_each_sample(run_id, [&](const Sample& s) {
      if (!s.has(tf::kStep)) no_step = true;
      if (keys.empty()) step0 = s.step;
      keys.push_back(sample_key(run_id, s.k));
      // The run's clock is its control step count: the firmware's steps are
      // what the excitation was timed on, and the only clock a --sim-fast
      // run has (its time stamps are the host's, running far ahead).
      run.t.push_back(double(s.step - step0) / row.loop_rate_hz);
      for (int i = 0; i < run.m; ++i) run.u.push_back(s.has(tf::kU) ? double(s.u()[i]) : 0.0);
      for (int i = 0; i < run.w; ++i) run.l.push_back(s.w > 0 ? double(s.l[i]) : 0.0);
    });
    if (no_step) throw CliError(fmt::format("run {}'s samples carry no step count: they cannot be timed", run_id));
    if (keys.empty()) throw CliError(fmt::format("run {} has no samples: nothing to merge into", run_id));
  }
  const Capture cap = read_capture(csv_path, n, names);
  MergeReport r;
  r.capture_rows = cap.rows();
  r.samples = keys.size();
  if (offset_s) {
    r.offset_s = *offset_s;
  } else {
    const OffsetEstimate e = estimate_offset(run, cap);
    r.offset_s = e.offset_s;
    r.score = e.score;
    r.estimated = true;
  }
  // A capture's time stamps are rounded (to the microsecond, often): a row
  // a thousandth of a sample past the run's end is not outside it.
  const double slack = 1e-3 * (run.t.back() - run.t.front()) / double(std::max<size_t>(1, run.rows() - 1));
  for (double t : cap.t)
    if (t - r.offset_s >= run.t.front() - slack && t - r.offset_s <= run.t.back() + slack) ++r.rows_inside;
  const std::vector<double> y = resample(cap, run.t, r.offset_s);
  for (size_t k = 0; k < keys.size(); ++k)
    if (!std::isnan(y[k * size_t(n)])) ++r.samples_set;
  if (r.samples_set == 0)
    throw CliError(fmt::format("{}: with the offset {:+.3f} s the capture ({:.3f} .. {:.3f} s on its clock, {:.3f} .. "
                               "{:.3f} s on the run's) does not overlap run {} (0 .. {:.3f} s); nothing changed",
                               csv_path, r.offset_s, cap.t.front(), cap.t.back(), cap.t.front() - r.offset_s,
                               cap.t.back() - r.offset_s, run_id, run.t.back()));
  try {
    Db db(db_path, Db::Access::ReadWrite);
    db.exec("BEGIN IMMEDIATE");
    try {
      Stmt up = db.prepare("UPDATE samples SET y_true=? WHERE id=?");
      std::vector<float> v(static_cast<size_t>(n), 0.0f);
      for (size_t k = 0; k < keys.size(); ++k) {
        // Outside the capture the run has no measured output: NULL, never a
        // value left from another source beside the capture's.
        if (std::isnan(y[k * size_t(n)])) {
          up.bind_null(1);
        } else {
          for (int j = 0; j < n; ++j) v[size_t(j)] = float(y[k * size_t(n) + size_t(j)]);
          up.bind_blob(1, v.data(), v.size() * sizeof(float));
        }
        up.bind(2, keys[k]);
        up.exec();
      }
      db.exec("COMMIT");
    } catch (...) {
      sqlite3_exec(db.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  } catch (const DbError& e) {
    throw CliError(fmt::format("run {} unchanged: {}", run_id, e.what()));
  }
  return r;
}

std::string merge_words(int64_t run_id, const std::string& csv_path, const MergeReport& r) {
  const double a = std::fabs(r.offset_s);
  std::string s = fmt::format("capture clock offset {}: {:+.3f} s (run time = capture time {} {:.3f} s); {} of {} "
                              "capture rows inside the run\n",
                              r.estimated ? "estimated" : "given", r.offset_s, r.offset_s < 0 ? "+" : "-", a,
                              grouped(r.rows_inside), grouped(r.capture_rows));
  s += fmt::format("run {}: measured outputs (y_true) of {} of {} samples set from {}", run_id, grouped(r.samples_set),
                   grouped(r.samples), csv_path);
  if (r.samples_set < r.samples)
    s += fmt::format("; the other {} {} outside the capture and {} none", grouped(r.samples - r.samples_set),
                     r.samples - r.samples_set == 1 ? "lies" : "lie", r.samples - r.samples_set == 1 ? "has" : "have");
  return s;
}

}  // namespace nlsoft::console
