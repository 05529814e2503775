#include "app/record/capture_offset.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <unsupported/Eigen/FFT>
#include <complex>
#include <algorithm>
#include <cmath>
#include <limits>

#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;

// How the offset is found (no library does this; it is a search over one
// number with a least-squares fit inside, Eigen doing the algebra and the
// FFT, unsupported/Eigen/FFT):
//
// At the right offset the capture's outputs follow the run's recorded
// inputs u (and sensors l, which respond to the same plant) causally: an
// ARX fit y(k) ~ y(k-1), y(k-2), u(k-1), l(k) explains the most of what the
// outputs' own past does not (the "innovation"). Shifted later by a sample,
// the input that drove a change is outside the one lag fitted (u(k-2) is
// left out on purpose: with it, one sample late fits as well as right);
// shifted earlier, the change comes before its cause: either way less is
// explained. The score is that explained innovation, SSE(AR alone) -
// SSE(ARX), over each output's variance, per run sample, summed over the
// outputs; unlike a plain correlation of levels it is not fooled by slow
// outputs (everything correlates with a shifted copy of itself) and needs
// no model of the rig, only that it is roughly linear over a step.
// The measured y the run may hold is not used: the capture is what is being
// placed, and a rig that needs one usually has none.
//
// The search is coarse to fine: every offset that leaves the two
// overlapping by half the shorter span at once, by cross-correlation
// (coarse_offset); then that fit around its peak, down to a sixteenth of a
// sample (the capture interpolated), on a stretch of at most 20 000 samples
// in the middle of the overlap: one offset holds for the whole run, and that
// many fix it (a 10-minute hasel run, 78 000 samples, 3 outputs, 6 inputs
// and 18 sensors, places in 1.5 s of CPU on the project machine).

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Linear interpolation of one output at times `ts` (ascending); NaN outside.
void interpolate(const Capture& cap, const std::vector<double>& ts, double offset_s, int j, std::vector<double>& out) {
  out.assign(ts.size(), kNaN);
  size_t c = 0;
  const size_t rows = cap.rows();
  for (size_t k = 0; k < ts.size(); ++k) {
    double x = ts[k] + offset_s;
    // A nanosecond's rounding at either end is not outside the capture.
    if (x < cap.t.front() && x > cap.t.front() - 1e-9) x = cap.t.front();
    if (x > cap.t.back() && x < cap.t.back() + 1e-9) x = cap.t.back();
    if (x < cap.t.front() || x > cap.t.back()) continue;
    while (c + 1 < rows && cap.t[c + 1] < x) ++c;
    if (c + 1 >= rows) {
      out[k] = cap.y[c * size_t(cap.n) + size_t(j)];
      continue;
    }
    const double t0 = cap.t[c], t1 = cap.t[c + 1];
    const double a = (x - t0) / (t1 - t0);
    const double y0 = cap.y[c * size_t(cap.n) + size_t(j)], y1 = cap.y[(c + 1) * size_t(cap.n) + size_t(j)];
    out[k] = y0 + std::clamp(a, 0.0, 1.0) * (y1 - y0);
  }
}

struct Level {
  std::vector<double> t;          // the run's times at this level's samples
  std::vector<double> u, l;       // centred, rows of m / w
  int m = 0, w = 0;
};

// Every stride-th sample of [begin, end).
Level level_of(const RunSignals& run, size_t stride, size_t begin, size_t end, const std::vector<double>& u_mean,
               const std::vector<double>& l_mean) {
  Level lv;
  lv.m = run.m;
  lv.w = run.w;
  for (size_t k = begin; k < end && k < run.rows(); k += stride) {
    lv.t.push_back(run.t[k]);
    for (int i = 0; i < run.m; ++i) lv.u.push_back(run.u[k * size_t(run.m) + size_t(i)] - u_mean[size_t(i)]);
    for (int i = 0; i < run.w; ++i) lv.l.push_back(run.l[k * size_t(run.w) + size_t(i)] - l_mean[size_t(i)]);
  }
  return lv;
}

// The score at one offset; -inf when too few rows overlap.
double score_at(const Level& lv, const Capture& cap, const std::vector<double>& y_mean,
                const std::vector<double>& y_var, double offset_s, size_t min_rows) {
  const int m = lv.m, w = lv.w;
  const int p_ar = 3;
  const int p = p_ar + m + w;
  std::vector<double> y;
  Eigen::VectorXd x(p);
  double total = 0;
  int outputs = 0;
  for (int j = 0; j < cap.n; ++j) {
    interpolate(cap, lv.t, offset_s, j, y);
    Eigen::MatrixXd xtx = Eigen::MatrixXd::Zero(p, p);
    Eigen::VectorXd xtz = Eigen::VectorXd::Zero(p);
    double ztz = 0;
    size_t rows = 0;
    for (size_t k = 2; k < y.size(); ++k) {
      if (std::isnan(y[k]) || std::isnan(y[k - 1]) || std::isnan(y[k - 2])) continue;
      int c = 0;
      x[c++] = 1.0;
      x[c++] = y[k - 1] - y_mean[size_t(j)];
      x[c++] = y[k - 2] - y_mean[size_t(j)];
      for (int i = 0; i < m; ++i) {
        x[c++] = lv.u[(k - 1) * size_t(m) + size_t(i)];
      }
      for (int i = 0; i < w; ++i) x[c++] = lv.l[k * size_t(w) + size_t(i)];
      const double z = y[k] - y_mean[size_t(j)];
      xtx.selfadjointView<Eigen::Lower>().rankUpdate(x);
      xtz += z * x;
      ztz += z * z;
      ++rows;
    }
    if (rows < min_rows) return -std::numeric_limits<double>::infinity();
    xtx.triangularView<Eigen::Upper>() = xtx.transpose();
    // A whisker of ridge keeps a constant or collinear column (an input the
    // signal never moved, a sensor that copies another) from making the
    // system singular; it changes no well-posed fit.
    auto sse = [&](int q) {
      Eigen::MatrixXd a = xtx.topLeftCorner(q, q);
      for (int i = 0; i < q; ++i) a(i, i) += 1e-9 * (a(i, i) + 1.0);
      const Eigen::VectorXd b = xtz.head(q);
      const Eigen::VectorXd beta = a.ldlt().solve(b);
      return std::max(0.0, ztz - beta.dot(b));
    };
    const double ar = sse(p_ar);
    if (!(ar > 1e-12 * (ztz + 1e-300)) || !(y_var[size_t(j)] > 0)) continue;  // an output that never moves tells nothing
    total += (ar - sse(p)) / (y_var[size_t(j)] * double(lv.t.size()));
    ++outputs;
  }
  return outputs > 0 ? total / outputs : 0.0;
}

// The coarse search, over every offset at once: the capture resampled at
// the run's period, and each output's changes cross-correlated (FFT) with
// each of the run's inputs' and sensors' changes, every series scaled to
// unit variance; the offset whose correlations, squared and summed, are
// largest. Changes, not levels: a PRBS's changes are spikes, a sensor's
// change comes with the output's, so the peak is narrow. Sums, not means:
// where the excitation repeats (a PRBS's period) the alignment that
// overlaps the most wins. The result is within a plant's lag of the
// offset; the fit refines it.
double coarse_offset(const RunSignals& run, const Capture& cap, double period, double lo, double hi) {
  const size_t K = run.rows();
  const size_t Q = size_t(std::floor((cap.t.back() - cap.t.front()) / period)) + 1;
  // Transforms of 2^22 points are 64 MiB each; a capture longer than that
  // at the run's rate (hours beside a 1 kHz run) is cut or placed by hand.
  constexpr size_t kMaxPoints = size_t(1) << 22;
  if (K + Q > kMaxPoints)
    throw CliError(fmt::format("{}: the capture spans {:.0f} s, {} points at the run's {:g} Hz, too long to search "
                               "every offset of (at most {} with the run's {}): cut it to the run's neighbourhood or "
                               "give the offset (--offset, --y-offset)",
                               cap.path, cap.t.back() - cap.t.front(), Q, 1.0 / period, kMaxPoints, K));
  size_t N = 1;
  while (N < K + Q) N *= 2;
  std::vector<double> grid_t(Q);
  for (size_t q = 0; q < Q; ++q) grid_t[q] = std::min(cap.t.back(), cap.t.front() + double(q) * period);
  // Changes of a series, centred and scaled to unit variance, zero-padded to N.
  auto changes = [N](const std::vector<double>& v) {
    std::vector<double> d(N, 0.0);
    if (v.size() < 2) return d;
    double mean = 0, var = 0;
    for (size_t k = 1; k < v.size(); ++k) mean += (v[k] - v[k - 1]) / double(v.size() - 1);
    for (size_t k = 1; k < v.size(); ++k) var += (v[k] - v[k - 1] - mean) * (v[k] - v[k - 1] - mean);
    const double scale = var > 0 ? 1.0 / std::sqrt(var / double(v.size() - 1)) : 0.0;
    for (size_t k = 1; k < v.size(); ++k) d[k] = (v[k] - v[k - 1] - mean) * scale;
    return d;
  };
  // The outputs' transforms are kept (few), the run's signals' made one at
  // a time (a rig may have dozens): memory stays (n + 2) transforms.
  Eigen::FFT<double> fft;
  std::vector<std::vector<std::complex<double>>> cap_f(size_t(cap.n));
  std::vector<double> y;
  for (int j = 0; j < cap.n; ++j) {
    interpolate(cap, grid_t, 0.0, j, y);
    fft.fwd(cap_f[size_t(j)], changes(y));
  }
  std::vector<double> total(N, 0.0), v(K), c;
  std::vector<std::complex<double>> f, prod(N);
  for (int i = 0; i < run.m + run.w; ++i) {
    for (size_t k = 0; k < K; ++k)
      v[k] = i < run.m ? run.u[k * size_t(run.m) + size_t(i)] : run.l[k * size_t(run.w) + size_t(i - run.m)];
    fft.fwd(f, changes(v));
    for (const auto& g : cap_f) {
      for (size_t q = 0; q < N; ++q) prod[q] = std::conj(f[q]) * g[q];
      fft.inv(c, prod);
      for (size_t q = 0; q < N; ++q) total[q] += c[q] * c[q];
    }
  }
  // Lag L (run sample k meets grid point k + L) is at index L mod N; its
  // offset is the grid's start plus L periods less the run's start.
  double best = lo, best_score = -1;
  for (long L = -long(K) + 1; L < long(Q); ++L) {
    const double off = cap.t.front() + double(L) * period - run.t.front();
    if (off < lo || off > hi) continue;
    const double sc = total[size_t((L + long(N)) % long(N))];
    if (sc > best_score) best_score = sc, best = off;
  }
  return best;
}

}  // namespace

OffsetEstimate estimate_offset(const RunSignals& run, const Capture& cap) {
  if (run.rows() < 8) throw CliError(fmt::format("the run has {} samples: too few to place a capture by", run.rows()));
  const double run_span = run.t.back() - run.t.front(), cap_span = cap.t.back() - cap.t.front();
  const double need = 0.5 * std::min(run_span, cap_span);
  // overlap(off) = min(run_end + off, cap_end) - max(run_start + off, cap_start) >= need
  const double lo = cap.t.front() - run.t.back() + need, hi = cap.t.back() - run.t.front() - need;
  if (lo > hi)
    throw CliError(fmt::format("{}: no capture clock offset lets the capture ({:.3f} s) and the run ({:.3f} s) overlap "
                               "by half the shorter: give it with --y-offset",
                               cap.path, cap_span, run_span));
  const double period = run_span / double(run.rows() - 1);
  std::vector<double> u_mean(size_t(run.m), 0.0), l_mean(size_t(run.w), 0.0), y_mean(size_t(cap.n), 0.0);
  for (size_t k = 0; k < run.rows(); ++k) {
    for (int i = 0; i < run.m; ++i) u_mean[size_t(i)] += run.u[k * size_t(run.m) + size_t(i)] / double(run.rows());
    for (int i = 0; i < run.w; ++i) l_mean[size_t(i)] += run.l[k * size_t(run.w) + size_t(i)] / double(run.rows());
  }
  for (size_t r = 0; r < cap.rows(); ++r)
    for (int j = 0; j < cap.n; ++j) y_mean[size_t(j)] += cap.y[r * size_t(cap.n) + size_t(j)] / double(cap.rows());
  std::vector<double> y_var(size_t(cap.n), 0.0);
  for (size_t r = 0; r < cap.rows(); ++r)
    for (int j = 0; j < cap.n; ++j) {
      const double d = cap.y[r * size_t(cap.n) + size_t(j)] - y_mean[size_t(j)];
      y_var[size_t(j)] += d * d / double(cap.rows());
    }
  // A constant capture fits every offset alike: the one found would be noise.
  // (Constant to rounding: the mean of n equal values need not be that value.)
  bool constant = true;
  for (int j = 0; j < cap.n; ++j)
    constant = constant && !(y_var[size_t(j)] > 1e-20 * (1 + y_mean[size_t(j)] * y_mean[size_t(j)]));
  if (constant)
    throw CliError(fmt::format("{}: every output is constant over the capture: it holds nothing to place it on the "
                               "run's clock by; give the offset with --y-offset",
                               cap.path));

  // A fit needs more rows than it has terms, and then some; and a candidate
  // must see the capture over most of what it could.
  const size_t terms = size_t(3 + run.m + run.w);
  auto min_rows = [&](const Level& lv) {
    return std::max<size_t>(3 * terms, size_t(double(lv.t.size()) * std::min(1.0, need / std::max(run_span, 1e-9)) / 2));
  };
  OffsetEstimate best{coarse_offset(run, cap, period, lo, hi), -std::numeric_limits<double>::infinity()};

  // The fit's stretch: at most kFineSamples in the middle of the overlap.
  constexpr size_t kFineSamples = 20000;
  size_t begin = 0, end = run.rows();
  if (run.rows() > kFineSamples) {
    const double from = std::max(run.t.front(), cap.t.front() - best.offset_s),
                 to = std::min(run.t.back(), cap.t.back() - best.offset_s);
    const double mid = 0.5 * (from + to);
    const size_t centre = size_t(std::lower_bound(run.t.begin(), run.t.end(), mid) - run.t.begin());
    begin = centre > kFineSamples / 2 ? centre - kFineSamples / 2 : 0;
    end = std::min(run.rows(), begin + kFineSamples);
    begin = end - kFineSamples;
  }
  const Level lv = level_of(run, 1, begin, end, u_mean, l_mean);
  auto consider = [&](double off) {
    const double sc = score_at(lv, cap, y_mean, y_var, off, min_rows(lv));
    if (sc > best.score) best = {off, sc};
  };
  // The correlation's peak lies where the outputs answer the inputs, a
  // plant's lag after the alignment: the fit searches 64 samples either
  // side, every 8th, then every 2nd and every sample around the best, then
  // a quarter and a sixteenth of one.
  consider(best.offset_s);
  for (double step : {8.0, 2.0, 1.0, 0.25, 1.0 / 16}) {
    const double around = best.offset_s;
    const int reach = step == 8.0 ? 8 : 4;
    for (int i = -reach; i <= reach; ++i)
      if (i != 0) consider(std::clamp(around + i * step * period, lo, hi));
  }
  if (!std::isfinite(best.score))
    throw CliError(fmt::format("{}: too few capture rows fall inside the run to estimate the clock offset: give it with "
                               "--y-offset",
                               cap.path));
  return best;
}

std::vector<double> resample(const Capture& cap, const std::vector<double>& run_t, double offset_s) {
  std::vector<double> out(run_t.size() * size_t(cap.n), kNaN), one;
  for (int j = 0; j < cap.n; ++j) {
    interpolate(cap, run_t, offset_s, j, one);
    for (size_t k = 0; k < run_t.size(); ++k) out[k * size_t(cap.n) + size_t(j)] = one[k];
  }
  return out;
}

}  // namespace nlsoft::console
