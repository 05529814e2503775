#include "app/record/run_metrics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "app/record/task_space.hpp"
#include "app/record/utc_time.hpp"

namespace nlsoft::console {

namespace {

std::vector<float> floats(const std::string& text) {
  std::vector<float> out;
  std::istringstream in(text);
  float v;
  while (in >> v) out.push_back(v);
  return out;
}

}  // namespace

RunMetrics run_metrics(const RunRow& run, const RunSeries& s, const std::vector<float>& weights, uint64_t gaps,
                       const InputLimits& limits) {
  RunMetrics m;
  m.samples = s.rows();
  m.lost_frames = run.lost_frames;
  m.gaps = gaps;
  m.has_true = s.has_y_true;
  std::vector<float> w;
  if (weights.size() == size_t(s.n)) {
    const float top = *std::max_element(weights.begin(), weights.end());
    for (float q : weights) w.push_back(top > 0 && q / top < 1e-6f ? 0.0f : 1.0f);
  }
  const float* wp = w.empty() ? nullptr : w.data();
  if (s.has_y_ref && s.has_y_true) m.truth = tracking_metrics(s.y_ref, s.y_true, s.n, wp);
  if (s.has_y_ref && s.has_y_hat) m.predicted = tracking_metrics(s.y_ref, s.y_hat, s.n, wp);
  if (s.has_solver && !s.compute_us.empty()) {
    m.compute_p50_us = percentile(s.compute_us, 0.5);
    m.compute_p99_us = percentile(s.compute_us, 0.99);
    double it = 0;
    for (uint8_t i : s.iterations) it += i;
    m.mean_iterations = it / double(s.iterations.size());
  }
  {
    const TrackingMetrics& t = m.has_true ? m.truth : m.predicted;
    const std::vector<double> space = task_space(run.platform);
    std::vector<int> axes = t.tracked;
    if (axes.empty())
      for (int a = 0; a < int(t.rmse.size()); ++a) axes.push_back(a);
    if (!t.rmse.empty() && space.size() == t.rmse.size()) {
      double worst = 0;
      for (int a : axes)
        if (a >= 0 && size_t(a) < t.rmse.size()) worst = std::max(worst, t.rmse[size_t(a)] / space[size_t(a)]);
      m.nrmse_space = worst;
    }
  }
  {
    auto spans = [&](const std::vector<float>& v) {
      std::vector<double> out;
      if (s.n <= 0 || v.size() < size_t(s.n)) return out;
      for (int a = 0; a < s.n; ++a) {
        float lo = v[size_t(a)], hi = lo;
        for (size_t i = size_t(a); i < v.size(); i += size_t(s.n)) lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
        out.push_back(double(hi) - double(lo));
      }
      return out;
    };
    if (s.has_y_ref) m.ref_span = spans(s.y_ref);
    m.y_span = spans(s.has_y_true ? s.y_true : s.y_hat);
  }
  if (s.has_u && s.m > 0 && s.u.size() >= s.rows() * size_t(s.m)) {
    // a series built by hand may lack some rows' u
    std::vector<float> u(s.u.begin(), s.u.begin() + long(s.rows() * size_t(s.m)));
    const InputMetrics im = input_metrics(u, s.m, limits.lo, limits.hi);
    m.u_effort = im.u_effort;
    m.u_saturated = im.u_saturated;
  }
  m.loop_rate_hz = m.loop_rate_set_hz = run.loop_rate_hz;
  // A run whose firmware died half-way spans less in samples than it lasted:
  // both are reported, so neither passes for the other.
  const auto t0 = utc_seconds(run.started_at), t1 = utc_seconds(run.ended_at);
  if (t0 && t1 && *t1 >= *t0) m.wall_s = *t1 - *t0;
  if (s.rows() >= 2) {
    // time_us wraps every 71.6 min: sum the wrapped differences.
    double us = 0;
    for (size_t i = 1; i < s.rows(); ++i) us += double(uint32_t(s.time_us[i] - s.time_us[i - 1]));
    const double steps = double(s.step.back()) - double(s.step.front());
    if (us > 0 && steps > 0) m.loop_rate_hz = steps / (us * 1e-6), m.loop_rate_measured = true;
    m.duration_s = us * 1e-6;
  }
  return m;
}

namespace {

// Rows [begin, end) of the series, every field cut the same way.
RunSeries slice_rows(RunSeries s, size_t begin, size_t end) {
  end = std::min(end, s.rows());
  begin = std::min(begin, end);
  auto cut = [begin, end](auto& v, size_t per_row) {
    v.resize(std::min(v.size(), end * per_row));
    v.erase(v.begin(), v.begin() + std::min(v.size(), begin * per_row));
  };
  cut(s.step, 1);
  cut(s.time_us, 1);
  cut(s.y_ref, size_t(s.n));
  cut(s.y_hat, size_t(s.n));
  cut(s.y_true, size_t(s.n));
  cut(s.u, size_t(s.m));
  cut(s.cost, 1);
  cut(s.compute_us, 1);
  cut(s.iterations, 1);
  return s;
}

}  // namespace

RunMetrics run_metrics(RunStore& store, int64_t run_id, double skip_s, double window_s) {
  const RunRow run = store.run(run_id);
  RunSeries s = store.series(run_id);
  // By the firmware's step count, so decimation and gaps do not shift it.
  const double rate = run.loop_rate_hz > 0 ? run.loop_rate_hz : 1.0;
  const uint64_t step0 = s.rows() > 0 ? s.step[0] : 0;
  if (skip_s > 0 && s.rows() > 0) {
    const uint64_t first = step0 + uint64_t(std::llround(skip_s * rate));
    size_t rows = 0;
    while (rows < s.rows() && s.step[rows] < first) ++rows;
    const size_t total = s.rows();  // read before s is moved from
    s = slice_rows(std::move(s), rows, total);
  }
  if (window_s > 0 && s.rows() > 0) {
    const uint64_t end = step0 + uint64_t(std::llround((std::max(0.0, skip_s) + window_s) * rate));
    size_t rows = 0;
    while (rows < s.rows() && s.step[rows] < end) ++rows;
    s = slice_rows(std::move(s), 0, rows);
  }
  std::vector<float> q;
  InputLimits limits;
  for (const ParamRecord& p : store.params(run_id)) {
    if (!p.at_start) continue;
    if (p.name == "Q") q = floats(p.value);
    else if (p.name == "u_min") limits.lo = floats(p.value);
    else if (p.name == "u_max") limits.hi = floats(p.value);
  }
  return run_metrics(run, s, q, store.gaps(run_id).size(), limits);
}

std::string nrmse_words(double nrmse, bool percent) {
  if (!std::isfinite(nrmse)) return "n/a (the reference held still; see nrmse_space)";
  return percent ? fmt::format("{:.4f} ({:.2f} %)", nrmse, 100 * nrmse) : fmt::format("{:.4f}", nrmse);
}

const std::vector<std::string>& metric_names() {
  static const std::vector<std::string> names = {
      "rmse",       "nrmse",    "nrmse_space", "max_error", "rmse_hat", "nrmse_hat", "lost_frames",
      "loop_rate_hz", "compute_p50_us", "compute_p99_us", "iterations", "samples", "duration_s", "wall_s",
      "gaps",       "u_effort", "u_saturated", "rmse0",     "rmse1",    "rmse2"};
  return names;
}

std::string canonical_metric_name(const std::string& name) {
  // The short spellings scripts used before the names carried their units.
  static const std::pair<const char*, const char*> kAliases[] = {
      {"lost", "lost_frames"},          {"loop_rate", "loop_rate_hz"}, {"compute_p50", "compute_p50_us"},
      {"compute_p99", "compute_p99_us"}, {"duration", "duration_s"},    {"wall", "wall_s"}};
  for (const auto& [alias, canonical] : kAliases)
    if (name == alias) return canonical;
  return name;
}

bool known_metric(const std::string& metric) {
  const std::string name = canonical_metric_name(metric);
  for (const auto& m : metric_names())
    if (m == name) return true;
  return name.size() > 4 && name.compare(0, 4, "rmse") == 0 &&
         name.find_first_not_of("0123456789", 4) == std::string::npos;
}

std::optional<double> metric_value(const RunMetrics& m, const std::string& metric) {
  const std::string name = canonical_metric_name(metric);
  // Tracking is judged on the true plant output when the firmware sends it,
  // on the model's prediction otherwise.
  const TrackingMetrics& t = m.has_true ? m.truth : m.predicted;
  auto worst = [](const TrackingMetrics& x) {
    return x.rmse.empty() ? 0.0 : *std::max_element(x.rmse.begin(), x.rmse.end());
  };
  // No tracking error from no samples: an empty rmse is no error of 0,
  // and neither is the max_error nothing was measured for.
  const bool tracked = !t.rmse.empty();
  if (!tracked && (name == "rmse" || name == "max_error")) return std::nullopt;
  if (m.predicted.rmse.empty() && (name == "rmse_hat" || name == "nrmse_hat")) return std::nullopt;
  if (name == "rmse") return worst(t);
  if (name == "nrmse") return t.nrmse;
  if (name == "nrmse_space") return m.nrmse_space;
  if (name == "max_error") return t.max_error;
  if (name == "rmse_hat") return worst(m.predicted);
  if (name == "nrmse_hat") return m.predicted.nrmse;
  if (name == "lost_frames") return double(m.lost_frames);
  if (name == "loop_rate_hz") return m.loop_rate_hz;
  if (name == "compute_p50_us") return m.compute_p50_us;
  if (name == "compute_p99_us") return m.compute_p99_us;
  if (name == "iterations") return m.mean_iterations;
  if (name == "samples") return double(m.samples);
  if (name == "duration_s") return m.duration_s;
  if (name == "wall_s") return m.wall_s;
  if (name == "gaps") return double(m.gaps);
  if (name == "u_effort") return m.u_effort;
  if (name == "u_saturated") return m.u_saturated;
  if (name.size() > 4 && name.compare(0, 4, "rmse") == 0) {
    char* end = nullptr;
    const long i = std::strtol(name.c_str() + 4, &end, 10);
    if (*end == '\0' && i >= 0 && size_t(i) < t.rmse.size()) return t.rmse[size_t(i)];
  }
  return std::nullopt;
}

}  // namespace nlsoft::console
