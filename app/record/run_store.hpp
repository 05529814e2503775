#pragma once
// Reading recorded runs back: the run list, one run's samples as columns
// (what metrics and plots want), its parameters, gaps and link events.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/record/sample.hpp"
#include "app/record/sqlite.hpp"

namespace nlsoft::console {

struct RunRow {
  int64_t id = 0;
  std::string started_at, ended_at, label, notes, platform, firmware, reference, end_reason;
  uint32_t model_hash = 0, param_hash = 0;
  double loop_rate_hz = 0;
  int n = 0, m = 0, decimation = 1;
  uint64_t samples = 0, lost_frames = 0;
  std::string kind = "control";  // "ident": an identification run (schema v6)
  int w = 0;                     // sensors kept per sample
  std::string excitation;        // JSON, identification runs
};

// A run's samples, one vector per field (rows of n or m for vectors).
struct RunSeries {
  int n = 0, m = 0, w = 0;
  std::vector<float> l;  // rows of w sensor values (identification runs)
  bool has_l = false;
  std::vector<uint32_t> step, time_us;
  std::vector<float> y_ref, y_hat, y_true, u, cost, compute_us;
  std::vector<uint8_t> iterations;
  bool has_y_ref = false, has_y_hat = false, has_y_true = false, has_u = false, has_solver = false;
  size_t rows() const { return step.size(); }
};

struct ParamRecord {
  double t = 0;
  bool at_start = false;
  std::string name, value;
};

struct GapRecord {
  std::string t, reason;
  uint64_t after_k = 0, lost_frames = 0;
  double duration_s = -1;  // < 0: not known
};

// SENSOR_HEALTH as recorded (schema v7): bit i of `invalid` is sensor
// channel i holding no valid chip sample at that step.
struct SensorHealthRecord {
  uint32_t invalid = 0;
  uint16_t age_ms = 0;
};

// Whether sensor channel i was invalid by a SENSOR_HEALTH mask: channels
// past the mask's 32 bits (a run may keep up to 58 sensors) are not covered.
inline bool channel_invalid(uint32_t invalid, size_t i) { return i < 32 && ((invalid >> i) & 1u) != 0; }

class RunStore {
 public:
  // Throws DbError; a missing file is an error in words, not a new database.
  explicit RunStore(const std::string& path);

  std::vector<RunRow> list();
  RunRow run(int64_t id);  // throws CliError "no run N"
  RunSeries series(int64_t id);
  void for_each_sample(int64_t id, const std::function<void(const Sample&)>& f);
  std::vector<ParamRecord> params(int64_t id);
  std::vector<GapRecord> gaps(int64_t id);
  // By step; empty for a run whose rig has no chips (or a file older than v7).
  std::map<uint32_t, SensorHealthRecord> sensor_health(int64_t id);
  std::vector<std::pair<std::string, std::string>> link_events(int64_t id);  // kind, detail
  int64_t last_run_id();  // 0 if none
  bool read_only() const;  // opened read-only (the usual case: reading never writes)

 private:
  void count_unfinished(RunRow& r);
  std::string run_columns() const;
  std::string path_;
  std::unique_ptr<Db> db_;
  int version_ = 0;  // the schema read (older than the console's when the file cannot be upgraded)
};

}  // namespace nlsoft::console
