#include "app/model/recorded_run.hpp"

#include <cmath>
#include <sstream>

#include "app/model/atomic_file.hpp"
#include "app/model/error.hpp"

namespace nlsoft::model {
namespace {

std::string dims(int m, int n) { return "m=" + std::to_string(m) + " n=" + std::to_string(n); }

bool all_finite(const std::vector<double>& v, long row, int count) {
  for (int i = 0; i < count; ++i)
    if (!std::isfinite(v[size_t(row) * size_t(count) + size_t(i)])) return false;
  return true;
}

// Whether sample b follows sample a by one control step: the firmware's
// step count says it when both carry one; otherwise k and the time stamps.
bool follows(const RecordedRun& r, long a, long b, double rate_hz) {
  if (b != a + 1 || r.k[size_t(b)] != r.k[size_t(a)] + 1) return false;
  const int64_t sa = r.step[size_t(a)], sb = r.step[size_t(b)];
  if (sa >= 0 && sb >= 0) return uint32_t(uint64_t(sb) - uint64_t(sa)) == 1u;
  const int64_t ta = r.time_us[size_t(a)], tb = r.time_us[size_t(b)];
  if (ta >= 0 && tb >= 0 && rate_hz > 0) {
    const double dt = double(uint32_t(uint64_t(tb) - uint64_t(ta))), period = 1e6 / rate_hz;
    return dt > 0.5 * period && dt < 1.5 * period;
  }
  return true;
}

int64_t integer_cell(double v) { return std::isfinite(v) && v >= 0 ? int64_t(v) : -1; }

// The columns prefix0, prefix1, ... of a header, by name (not position:
// an export of a run with sensors adds l0.. columns).
std::vector<int> prefixed(const std::vector<std::string>& h, const std::string& prefix) {
  std::vector<int> cols;
  for (;;) {
    const std::string want = prefix + std::to_string(cols.size());
    int at = -1;
    for (size_t c = 0; c < h.size(); ++c)
      if (h[c] == want) at = int(c);
    if (at < 0) return cols;
    cols.push_back(at);
  }
}

// A run's sample counter and clock only move forward; its clock is 32-bit
// microseconds, so a wrap goes back by nearly 2^32 us, and a row whose time
// goes back by less is out of order (rows sorted by hand, two files joined).
void refuse_going_back(const RecordedRun& r, const Table& t, long row, const std::string& name) {
  // A table read from text knows its lines; one built in memory, its rows (after a header).
  const auto line = [&](long i) { return size_t(i) < t.line.size() ? t.line[size_t(i)] : i + 2; };
  const auto at = [&](long i) { return name + ":" + std::to_string(line(i)); };
  const int64_t ka = r.k[size_t(row - 1)], kb = r.k[size_t(row)];
  if (ka >= 0 && kb >= 0 && kb <= ka)
    throw PipelineError(at(row) + ": k " + std::to_string(kb) + " does not follow k " + std::to_string(ka) + " (line " +
                        std::to_string(line(row - 1)) + "): a run's samples come in order");
  const int64_t ta = r.time_us[size_t(row - 1)], tb = r.time_us[size_t(row)];
  if (ta >= 0 && tb >= 0 && tb < ta && ta - tb < (int64_t(1) << 31))
    throw PipelineError(at(row) + ": time_us " + std::to_string(tb) + " is before the previous row's " +
                        std::to_string(ta) + " (line " + std::to_string(line(row - 1)) +
                        "): a run's clock only moves forward (a 32-bit wrap goes back by nearly 2^32 us)");
}

}  // namespace

Series recorded_series(const RecordedRun& r, const PlantTarget& t) {
  if (!r.rig.empty() && r.rig != t.name)
    throw PipelineError(r.name + " was recorded on rig '" + r.rig + "', not on rig '" + t.name +
                        "' (--rig): a model learnt on one rig does not describe another");
  if (r.rows() == 0) throw PipelineError(r.name + " has no samples: there is nothing to train on");
  if (r.m != t.m || r.n != t.n)
    throw PipelineError(r.name + " has " + dims(r.m, r.n) + ", rig '" + t.name + "' has " + dims(t.m, t.n));
  bool any_y = false, any_u = false;
  for (long i = 0; i < r.rows(); ++i) {
    any_y = any_y || all_finite(r.y, i, r.n);
    any_u = any_u || all_finite(r.u, i, r.m);
  }
  if (!any_y)
    throw PipelineError(r.name + " has no measured output (y_true): its firmware measured none, and a model is " +
                        "learnt from measured outputs, not from its own predictions (y_hat)");
  if (!any_u) throw PipelineError(r.name + " recorded no commands u");
  if (t.w > 0 && r.w < 0)
    throw PipelineError(r.name + " holds no sensor readings l, and rig '" + t.name + "' has " + std::to_string(t.w) +
                        " sensors its model reads (a closed-loop run holds them when its firmware streams them, "
                        "protocol 1.6 SENSOR_STREAM; an older firmware's runs hold y_ref, y_hat, y_true and u only)");
  const int w = std::max(r.w, 0);
  if (w != t.w)
    throw PipelineError(r.name + " has " + std::to_string(w) + " sensor readings, rig '" + t.name + "' has " +
                        std::to_string(t.w));

  std::vector<long> keep;
  for (long i = 0; i < r.rows(); ++i)
    if (all_finite(r.u, i, r.m) && all_finite(r.y, i, r.n) && (w == 0 || all_finite(r.l, i, w))) keep.push_back(i);
  Series s;
  s.resize(long(keep.size()), r.m, r.n, w);
  s.name = r.name;
  const double period = t.rate_hz > 0 ? 1.0 / t.rate_hz : 0.0;
  double time = 0;
  for (size_t j = 0; j < keep.size(); ++j) {
    const long i = keep[j];
    if (j > 0) {
      const long a = keep[j - 1];
      if (!follows(r, a, i, t.rate_hz)) s.breaks.push_back(long(j));
      // The firmware's clock (32-bit microseconds, unwrapped), else its steps at the rig's rate.
      const int64_t ta = r.time_us[size_t(a)], ti = r.time_us[size_t(i)];
      const int64_t sa = r.step[size_t(a)], si = r.step[size_t(i)];
      if (ta >= 0 && ti >= 0)
        time += double(uint32_t(uint64_t(ti) - uint64_t(ta))) * 1e-6;
      else if (sa >= 0 && si >= 0)
        time += double(uint32_t(uint64_t(si) - uint64_t(sa))) * period;
      else
        time += period;
    }
    s.time(long(j)) = time;
    for (int c = 0; c < r.m; ++c) s.u(long(j), c) = r.u[size_t(i) * size_t(r.m) + size_t(c)];
    for (int c = 0; c < r.n; ++c) s.y(long(j), c) = r.y[size_t(i) * size_t(r.n) + size_t(c)];
    for (int c = 0; c < w; ++c) s.l(long(j), c) = r.l[size_t(i) * size_t(w) + size_t(c)];
  }
  // No two samples a control step apart: telemetry decimated (every d-th
  // step sent), which no lag window can be built from.
  if (keep.size() > 2 && s.breaks.size() == keep.size() - 1) {
    const int64_t a = r.step[size_t(keep[0])], b = r.step[size_t(keep[1])];
    const std::string apart = a >= 0 && b >= 0 ? std::to_string(uint32_t(uint64_t(b) - uint64_t(a))) + " control steps"
                                               : "more than a control step";
    throw PipelineError(r.name + ": no two samples are one control step apart (the first two are " + apart +
                        " apart: telemetry decimated?); the model steps one control period: record with "
                        "--decimation 1");
  }
  return s;
}

bool is_run_export(const std::vector<std::string>& h) {
  return h.size() >= 3 && h[0] == "k" && h[1] == "step" && h[2] == "time_us";
}

RecordedRun run_from_export(const Table& t, const std::string& name) {
  const std::vector<std::string>& h = t.header;
  const std::vector<int> u = prefixed(h, "u"), y = prefixed(h, "y_true"), l = prefixed(h, "l");
  if (u.empty() || y.empty())
    throw PipelineError(name + ": a run export needs columns u0.. and y_true0.. (as `nlsoft-console runs export ID "
                               "--csv` writes them)");
  RecordedRun r;
  r.name = name;
  r.m = int(u.size());
  r.n = int(y.size());
  r.w = l.empty() ? -1 : int(l.size());
  for (long row = 0; row < t.rows; ++row) {
    r.k.push_back(integer_cell(t.at(row, 0)));
    r.step.push_back(integer_cell(t.at(row, 1)));
    r.time_us.push_back(integer_cell(t.at(row, 2)));
    if (row > 0) refuse_going_back(r, t, row, name);
    // The run holds float32 values and the export writes each with 9
    // digits, which names that float exactly: rounding to float gives back
    // the very value the database holds (strtod alone lands on a double near it).
    for (int c : u) r.u.push_back(double(float(t.at(row, c))));
    for (int c : y) r.y.push_back(double(float(t.at(row, c))));
    for (int c : l) r.l.push_back(double(float(t.at(row, c))));
  }
  return r;
}

Series read_training_csv(const std::string& path, const PlantTarget& target) {
  const std::string text = without_bom(read_text_file(path, {"CSV file", uint64_t(1) << 30}));
  std::istringstream lines(text);
  std::string first;
  while (std::getline(lines, first) && first.find_first_not_of(" \t\r") == std::string::npos) {
  }
  const size_t b = first.find_first_not_of(" \t");
  const std::string head = b == std::string::npos ? "" : first.substr(b);
  std::istringstream in(text);
  if (head.rfind("time", 0) == 0) return parse_series_csv(in, path);
  if (head.rfind("k,step,time_us", 0) == 0)
    return recorded_series(run_from_export(parse_csv(in, path, true, true), path), target);
  // Neither: read as a dataset, which names a bad cell first, then the header.
  return parse_series_csv(in, path);
}

}  // namespace nlsoft::model
