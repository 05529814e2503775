#include "app/record/run_store.hpp"

#include <sqlite3.h>

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>

#include "host/files/cli_error.hpp"
#include "app/record/row_columns.hpp"
#include "app/record/schema.hpp"

namespace nlsoft::console {

using host::CliError;

namespace tf = protocol::telemetry_field;

namespace {

// An int64 column as an int: out of int's range reads as -1, which
// check_counts() refuses (a plain cast would wrap 2^32 + 1 to 1).
template <auto field>
void read_count(const Stmt& s, int col, RunRow& r) {
  const int64_t v = s.int64(col);
  r.*field = v < 0 || v > 0x7FFFFFFF ? -1 : int(v);
}

const Column<RunRow> kRunColumns[] = {
    {"id", read_field<&RunRow::id>},
    {"started_at", read_field<&RunRow::started_at>},
    {"ifnull(ended_at,'')", read_field<&RunRow::ended_at>},
    {"label", read_field<&RunRow::label>},
    {"notes", read_field<&RunRow::notes>},
    {"platform", read_field<&RunRow::platform>},
    {"firmware", read_field<&RunRow::firmware>},
    {"reference", read_field<&RunRow::reference>},
    {"ifnull(end_reason,'')", read_field<&RunRow::end_reason>},
    {"model_hash", read_field<&RunRow::model_hash>},
    {"param_hash", read_field<&RunRow::param_hash>},
    {"loop_rate_hz", read_field<&RunRow::loop_rate_hz>},
    {"n", read_count<&RunRow::n>},
    {"m", read_count<&RunRow::m>},
    {"decimation", read_field<&RunRow::decimation>},
    {"samples", read_field<&RunRow::samples>},
    {"lost_frames", read_field<&RunRow::lost_frames>},
};

// Schema v6's columns of an identification run, after kRunColumns.
const Column<RunRow> kRunColumnsV6[] = {
    {"kind", read_field<&RunRow::kind>},
    {"w", read_count<&RunRow::w>},
    {"excitation", read_field<&RunRow::excitation>},
};

// A run's counts size the fixed arrays its samples are read into (Sample:
// n outputs three times and m inputs in v, w sensors in l): checked here,
// where the file's bytes become a RunRow, so no reader ever sizes anything
// from an unchecked count.
void check_counts(const std::string& path, const RunRow& r) {
  auto bad = [&](const char* what, int64_t v, int max) {
    throw CliError(fmt::format("database {}: run {} is damaged or not written by nlsoft-console: {} = {}, where a run "
                               "has 0 to {}",
                               path, r.id, what, v, max));
  };
  if (r.n < 0 || r.n > protocol::kMaxTelemetryDim) bad("n (outputs)", r.n, protocol::kMaxTelemetryDim);
  if (r.m < 0 || r.m > protocol::kMaxTelemetryDim) bad("m (inputs)", r.m, protocol::kMaxTelemetryDim);
  if (r.w < 0 || r.w > Sample::kMaxSensors) bad("w (sensors)", r.w, Sample::kMaxSensors);
}

RunRow read_run(const Stmt& s, bool v6, const std::string& path) {
  RunRow r;
  const int next = read_columns(s, kRunColumns, r);
  if (v6) read_columns(s, kRunColumnsV6, r, next);
  check_counts(path, r);
  return r;
}

// Copies a float blob into v (count floats, what the run's n, m or w say,
// checked against v's room by check_counts()); false if NULL. A blob of
// any other size is a damaged run, refused: its bytes are not the run's.
bool read_floats(const Stmt& s, int col, float* v, int count, const std::string& path, int64_t run, int64_t k,
                 const char* field, const char* count_name) {
  if (s.is_null(col)) return false;
  size_t n = 0;
  const void* p = s.blob(col, n);
  if (n != size_t(count) * 4 || (n > 0 && p == nullptr))
    throw CliError(fmt::format("database {}: run {} is damaged or not written by nlsoft-console: sample {} holds {} "
                               "bytes of {}, where {} = {} makes {}",
                               path, run, k, n, field, count_name, count, size_t(count) * 4));
  if (n > 0) std::memcpy(v, p, n);
  return true;
}

}  // namespace

RunStore::RunStore(const std::string& path) : path_(path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw CliError(fmt::format("no recordings yet: database {} does not exist (record a run first, or pick one with --db)", path));
  db_ = std::make_unique<Db>(path, Db::Access::ReadOnly);
  const int v = schema_version(*db_);
  if (v == 0) throw CliError(fmt::format("{} is not an nlsoft recording database", path));
  // Older files are upgraded in place so every reader sees one schema; that
  // takes the one write a reader ever makes.
  // takes the one write a reader ever makes. A file we may not write (a
  // read-only copy, someone else's) is read at its own version: v2 lacks
  // only the gaps' durations.
  if (v < kSchemaVersion && ::access(path.c_str(), W_OK) == 0) {
    try {
      auto rw = std::make_unique<Db>(path, Db::Access::ReadWrite);
      migrate(*rw);
      db_ = std::move(rw);
      version_ = kSchemaVersion;
    } catch (const DbError&) {
      if (v < 2)
        throw CliError(fmt::format("{} has schema v{} and cannot be upgraded to v{} here (read-only)", path, v,
                                   kSchemaVersion));
      version_ = v;
    }
  } else {
    if (v < 2)
      throw CliError(fmt::format("{} has schema v{} and cannot be upgraded to v{} here (read-only)", path, v,
                                 kSchemaVersion));
    version_ = v;
  }
  if (v > kSchemaVersion)
    throw CliError(fmt::format("database {} has schema v{}, newer than this console's v{}", path, v, kSchemaVersion));
}

std::string RunStore::run_columns() const {
  return select_list(kRunColumns) + (version_ >= 6 ? "," + select_list(kRunColumnsV6) : "");
}

std::vector<RunRow> RunStore::list() {
  Stmt s = db_->prepare(fmt::format("SELECT {} FROM runs ORDER BY id", run_columns()).c_str());
  std::vector<RunRow> out;
  while (s.step()) out.push_back(read_run(s, version_ >= 6, path_));
  for (RunRow& r : out) count_unfinished(r);
  return out;
}

// A run cut short by a crash has no totals yet: count what is there.
void RunStore::count_unfinished(RunRow& r) {
  if (!r.ended_at.empty()) return;
  Stmt c = db_->prepare("SELECT count(*) FROM samples WHERE id BETWEEN ? AND ?");
  c.bind(1, sample_key(r.id, 0)).bind(2, sample_key(r.id, 0xFFFFFFFFu));
  if (c.step()) r.samples = uint64_t(c.int64(0));
  Stmt g = db_->prepare("SELECT ifnull(sum(lost_frames),0) FROM gaps WHERE run_id=?");
  g.bind(1, r.id);
  if (g.step()) r.lost_frames = uint64_t(g.int64(0));
}

RunRow RunStore::run(int64_t id) {
  Stmt s = db_->prepare(fmt::format("SELECT {} FROM runs WHERE id=?", run_columns()).c_str());
  s.bind(1, id);
  if (!s.step()) {
    const int64_t last = last_run_id();
    throw CliError(last ? fmt::format("no run {} (runs are numbered 1..{}; see `nlsoft-console runs list`)", id, last)
                        : fmt::format("no run {}: nothing recorded yet", id));
  }
  RunRow r = read_run(s, version_ >= 6, path_);
  count_unfinished(r);
  return r;
}

bool RunStore::read_only() const { return sqlite3_db_readonly(db_->handle(), "main") == 1; }

int64_t RunStore::last_run_id() {
  Stmt s = db_->prepare("SELECT ifnull(max(id),0) FROM runs");
  return s.step() ? s.int64(0) : 0;
}

void RunStore::for_each_sample(int64_t id, const std::function<void(const Sample&)>& f) {
  const RunRow r = run(id);
  Stmt s = db_->prepare(fmt::format("SELECT k,step,time_us,y_ref,y_hat,y_true,u,cost,iterations,compute_us,{} FROM "
                                    "samples WHERE id BETWEEN ? AND ? ORDER BY id",
                                    version_ >= 6 ? "l" : "NULL")
                            .c_str());
  s.bind(1, sample_key(id, 0)).bind(2, sample_key(id, 0xFFFFFFFFu));
  // r's counts fit x (check_counts): n, m and w are what x holds.
  Sample x;
  x.n = uint8_t(r.n);
  x.m = uint8_t(r.m);
  const int w = r.w;
  while (s.step()) {
    x.k = uint64_t(s.int64(0));
    x.mask = 0;
    if (!s.is_null(1)) x.step = uint32_t(s.int64(1)), x.mask |= tf::kStep;
    if (!s.is_null(2)) x.time_us = uint32_t(s.int64(2)), x.mask |= tf::kTime;
    auto floats = [&](int col, float* v, int count, const char* field, const char* count_name) {
      return read_floats(s, col, v, count, path_, id, int64_t(x.k), field, count_name);
    };
    if (floats(3, x.y_ref(), r.n, "y_ref", "n")) x.mask |= tf::kYRef;
    if (floats(4, x.y_hat(), r.n, "y_hat", "n")) x.mask |= tf::kYHat;
    if (floats(5, x.y_true(), r.n, "y_true", "n")) x.mask |= tf::kYTrue;
    if (floats(6, x.u(), r.m, "u", "m")) x.mask |= tf::kU;
    if (!s.is_null(7)) x.cost = float(s.real(7)), x.mask |= tf::kCost;
    if (!s.is_null(8)) {
      x.iterations = uint8_t(s.int64(8));
      x.compute_us = float(s.real(9));
      x.mask |= tf::kSolver;
    }
    x.w = floats(10, x.l, w, "l (sensors)", "w") ? uint8_t(w) : 0;
    f(x);
  }
}

RunSeries RunStore::series(int64_t id) {
  RunSeries out;
  const RunRow r = run(id);
  out.n = r.n;
  out.m = r.m;
  out.w = r.w;
  bool first = true;
  for_each_sample(id, [&](const Sample& x) {
    if (first) {
      out.has_y_ref = x.has(tf::kYRef);
      out.has_y_hat = x.has(tf::kYHat);
      out.has_y_true = x.has(tf::kYTrue);
      out.has_u = x.has(tf::kU);
      out.has_solver = x.has(tf::kSolver);
      out.has_l = x.w > 0;
      first = false;
    }
    out.step.push_back(x.step);
    out.time_us.push_back(x.time_us);
    // Rows stay aligned even if a field is missing from one sample.
    for (int i = 0; i < out.n; ++i) {
      out.y_ref.push_back(x.has(tf::kYRef) ? x.y_ref()[i] : 0.0f);
      out.y_hat.push_back(x.has(tf::kYHat) ? x.y_hat()[i] : 0.0f);
      out.y_true.push_back(x.has(tf::kYTrue) ? x.y_true()[i] : 0.0f);
    }
    for (int i = 0; i < out.m; ++i) out.u.push_back(x.has(tf::kU) ? x.u()[i] : 0.0f);
    for (int i = 0; i < out.w; ++i) out.l.push_back(x.w > 0 ? x.l[i] : 0.0f);
    out.cost.push_back(x.cost);
    out.iterations.push_back(x.iterations);
    out.compute_us.push_back(x.compute_us);
  });
  return out;
}

std::vector<ParamRecord> RunStore::params(int64_t id) {
  Stmt s = db_->prepare("SELECT t,at_start,name,value FROM params WHERE run_id=? ORDER BY at_start DESC, t, rowid");
  s.bind(1, id);
  std::vector<ParamRecord> out;
  while (s.step()) out.push_back({s.real(0), s.int64(1) != 0, s.text(2), s.text(3)});
  return out;
}

std::vector<GapRecord> RunStore::gaps(int64_t id) {
  Stmt s = db_->prepare(
      version_ >= 3 ? "SELECT t,reason,after_k,lost_frames,ifnull(duration_s,-1) FROM gaps WHERE run_id=? ORDER BY after_k"
                    : "SELECT t,reason,after_k,lost_frames,-1 FROM gaps WHERE run_id=? ORDER BY after_k");
  s.bind(1, id);
  std::vector<GapRecord> out;
  while (s.step()) out.push_back({s.text(0), s.text(1), uint64_t(s.int64(2)), uint64_t(s.int64(3)), s.real(4)});
  return out;
}

std::map<uint32_t, SensorHealthRecord> RunStore::sensor_health(int64_t id) {
  std::map<uint32_t, SensorHealthRecord> out;
  if (version_ < 7) return out;
  Stmt s = db_->prepare("SELECT step,invalid,age_ms FROM sensor_health WHERE run_id=?");
  s.bind(1, id);
  while (s.step()) out[uint32_t(s.int64(0))] = {uint32_t(s.int64(1)), uint16_t(s.int64(2))};
  return out;
}

std::vector<std::pair<std::string, std::string>> RunStore::link_events(int64_t id) {
  Stmt s = db_->prepare("SELECT t || ' ' || kind, detail FROM link_events WHERE run_id=? ORDER BY id");
  s.bind(1, id);
  std::vector<std::pair<std::string, std::string>> out;
  while (s.step()) out.emplace_back(s.text(0), s.text(1));
  return out;
}

}  // namespace nlsoft::console
