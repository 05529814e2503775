#include "app/metrics/tracking_metrics.hpp"

#include <algorithm>
#include <cmath>

namespace nlsoft::console {

InputMetrics input_metrics(const std::vector<float>& u, int m, const std::vector<float>& lo,
                           const std::vector<float>& hi) {
  InputMetrics out;
  if (m <= 0) return out;
  const size_t mm = size_t(m), rows = u.size() / mm;
  if (rows == 0) return out;
  const bool known = lo.size() == mm && hi.size() == mm;
  auto range = [&](size_t i) {
    const double r = known ? double(hi[i]) - double(lo[i]) : 1.0;
    return r > 0 ? r : 1.0;
  };
  double sum = 0;
  size_t count = 0;
  for (size_t k = 1; k < rows; ++k)
    for (size_t i = 0; i < mm; ++i) {
      const double d = (double(u[k * mm + i]) - double(u[(k - 1) * mm + i])) / range(i);
      sum += d * d;
      ++count;
    }
  out.u_effort = count > 0 ? std::sqrt(sum / double(count)) : 0.0;
  if (!known) return out;
  out.saturated_per_input.assign(mm, 0.0);
  for (size_t k = 0; k < rows; ++k)
    for (size_t i = 0; i < mm; ++i) {
      const double tol = 0.01 * range(i), v = u[k * mm + i];
      if (v <= double(lo[i]) + tol || v >= double(hi[i]) - tol) out.saturated_per_input[i] += 1;
    }
  double total = 0;
  for (double& s : out.saturated_per_input) {
    total += s;
    s /= double(rows);
  }
  out.u_saturated = total / double(rows * mm);
  return out;
}

double percentile(std::vector<float> v, double p) {
  if (v.empty()) return 0.0;
  const size_t idx = std::min(v.size() - 1, size_t(std::lround(p * double(v.size() - 1))));
  std::nth_element(v.begin(), v.begin() + long(idx), v.end());
  return v[idx];
}

TrackingMetrics tracking_metrics(const std::vector<float>& y_ref, const std::vector<float>& y, int n,
                                 const float* weight) {
  TrackingMetrics m;
  const size_t rows = n > 0 ? y.size() / size_t(n) : 0;
  float wmax = 0.0f;
  for (int i = 0; weight && i < n; ++i) wmax = std::max(wmax, weight[i]);
  auto tracked = [&](int i) { return !weight || weight[i] >= 1e-3f * wmax; };
  for (int i = 0; i < n; ++i)
    if (tracked(i)) m.tracked.push_back(i);
  m.rmse.assign(size_t(n), 0.0);
  std::vector<double> lo(size_t(n), INFINITY), hi(size_t(n), -INFINITY);
  for (size_t k = 0; k < rows; ++k) {
    double dist2 = 0;
    for (int i = 0; i < n; ++i) {
      const double r = y_ref[k * size_t(n) + size_t(i)], e = double(y[k * size_t(n) + size_t(i)]) - r;
      m.rmse[size_t(i)] += e * e;
      if (tracked(i)) dist2 += e * e;
      lo[size_t(i)] = std::min(lo[size_t(i)], r);
      hi[size_t(i)] = std::max(hi[size_t(i)], r);
    }
    m.max_error = std::max(m.max_error, std::sqrt(dist2));
  }
  double worst = 0, range = 0, worst_all = 0, range_all = 0;
  for (int i = 0; i < n; ++i) {
    m.rmse[size_t(i)] = rows ? std::sqrt(m.rmse[size_t(i)] / double(rows)) : 0.0;
    const double r = rows ? hi[size_t(i)] - lo[size_t(i)] : 0.0;
    worst_all = std::max(worst_all, m.rmse[size_t(i)]);
    range_all = std::max(range_all, r);
    if (!tracked(i)) continue;
    worst = std::max(worst, m.rmse[size_t(i)]);
    range = std::max(range, r);
  }
  // A flat reference has no range to normalise by: NaN, so that no
  // `expect nrmse < x` can pass on it and JSON shows null, not 0 (perfect).
  m.nrmse = range > 0 ? worst / range : std::nan("");
  m.nrmse_all = range_all > 0 ? worst_all / range_all : std::nan("");
  return m;
}

std::vector<StepResponse> step_responses(const RefParams& ref, const std::vector<float>& y, int n, int axis,
                                         float dt) {
  std::vector<StepResponse> out;
  if (ref.kind != RefKind::Step) return out;
  const long hold = ref.hold == 0 ? 1 : ref.hold;
  const long rows = long(y.size()) / n;
  double from = ref.c[axis];
  for (int j = 0; j < ref.level_count; ++j) {
    StepResponse s;
    s.from = from;
    s.to = ref.c[axis] + ref.levels[j];
    // Row k holds y(k+1) and the level changes at k = j*hold (reference_at(k+1)).
    const long begin = j * hold - 1 < 0 ? 0 : j * hold - 1, end = std::min(rows, (j + 1) * hold - 1);
    if (end <= begin) break;
    const double delta = s.to - s.from, target = s.from + 0.9 * delta;
    // A predictive controller sees the next level coming and starts to move
    // before it: the last 10 % of a segment belongs to the next step, so
    // overshoot is read before it and the steady state in the 10 % ahead of it.
    const long len = end - begin, settled = end - len / 10, tail_from = end - len / 5;
    double peak = 0, tail = 0;
    long tail_n = 0;
    for (long k = begin; k < settled; ++k) {
      const double v = y[size_t(k) * size_t(n) + size_t(axis)];
      if (s.rise_s < 0 && (delta >= 0 ? v >= target : v <= target)) s.rise_s = double(k + 1 - begin) * double(dt);
      peak = std::max(peak, delta >= 0 ? v - s.to : s.to - v);
      if (k >= tail_from) tail += v, ++tail_n;
    }
    s.overshoot_pct = delta != 0 ? 100.0 * peak / std::fabs(delta) : 0.0;
    s.steady_error = tail_n ? std::fabs(tail / double(tail_n) - s.to) : 0.0;
    out.push_back(s);
    from = s.to;
  }
  return out;
}

}  // namespace nlsoft::console
