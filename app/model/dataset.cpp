#include "app/model/dataset.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "app/model/error.hpp"

namespace nlsoft::model {

Dataset build_dataset(const Series& s, int nd, int dd) {
  if (nd < 1 || dd < 1) throw PipelineError("nd and dd must be at least 1");
  const long q = s.rows();
  const int hist = std::max(nd, dd);
  // The stretches between breaks, and the rows each gives.
  std::vector<RowRange> stretches;
  long start = 0;
  for (long b : s.breaks) {
    if (b <= start || b >= q) continue;
    stretches.push_back({start, b});
    start = b;
  }
  stretches.push_back({start, q});
  long rows = 0;
  for (const RowRange& st : stretches) rows += std::max(0L, st.end - st.begin - hist);
  if (rows < 1) {
    const std::string who = s.name.empty() ? "the series" : s.name;
    if (stretches.size() == 1)
      throw PipelineError(who + " is too short for nd = " + std::to_string(nd) + ", dd = " + std::to_string(dd) +
                          " (" + std::to_string(q) + " samples)");
    throw PipelineError(who + ": no stretch between its gaps holds more than " + std::to_string(hist) +
                        " consecutive samples (" + std::to_string(stretches.size()) + " stretches in " +
                        std::to_string(q) + " samples)");
  }
  Dataset d;
  d.layout = InputLayout{s.m, s.n, s.w, nd, dd};
  const InputLayout& L = d.layout;
  d.first_k = hist - 1;
  d.X.resize(rows, L.p());
  d.Y.resize(rows, s.n);
  long r = 0;
  for (const RowRange& st : stretches) {
    const long first = r;
    for (long k = st.begin + hist - 1; k + 1 < st.end; ++k, ++r) {
      for (int lag = 0; lag < nd; ++lag)
        for (int i = 0; i < s.m; ++i) d.X(r, L.u_begin() + lag * s.m + i) = s.u(k - lag, i);
      for (int lag = 0; lag < dd; ++lag)
        for (int j = 0; j < s.n; ++j) d.X(r, L.y_begin() + lag * s.n + j) = s.y(k - lag, j);
      for (int i = 0; i < s.w; ++i) d.X(r, L.l_begin() + i) = s.l(k, i);
      for (int j = 0; j < s.n; ++j) d.Y(r, j) = s.y(k + 1, j);
    }
    if (r > first) d.pieces.push_back({first, r});
  }
  return d;
}

std::vector<RowRange> pieces_within(const Dataset& d, long begin, long end) {
  std::vector<RowRange> out;
  for (const RowRange& p : d.pieces) {
    const long b = std::max(p.begin, begin), e = std::min(p.end, end);
    if (e > b) out.push_back({b, e});
  }
  return out;
}

std::vector<RowRange> copy_rows(Dataset& into, long at, const Dataset& from, long begin, long end) {
  std::vector<RowRange> added;
  const long len = end - begin;
  if (len <= 0) return added;
  into.X.middleRows(at, len) = from.X.middleRows(begin, len);
  into.Y.middleRows(at, len) = from.Y.middleRows(begin, len);
  for (const RowRange& p : pieces_within(from, begin, end)) {
    into.pieces.push_back({p.begin - begin + at, p.end - begin + at});
    added.push_back(into.pieces.back());
  }
  return added;
}

namespace {

void set_range(Normalisation& nz, int col, double lo, double hi) {
  const double span = hi - lo;
  nz.in_offset(col) = 0.5 * (lo + hi);
  // A constant column (a dead sensor) passes through unscaled.
  nz.in_scale(col) = span > 1e-12 * std::max(1.0, std::abs(lo)) ? 1.0 / span : 1.0;
}

}  // namespace

Normalisation fit_normalisation(const Dataset& d, long rows, const NormalisationSpec& spec) {
  const InputLayout& L = d.layout;
  if (rows < 1 || rows > d.rows()) throw PipelineError("normalisation needs at least one training row");
  const Eigen::MatrixXd X = d.X.topRows(rows);
  const Eigen::MatrixXd Y = d.Y.topRows(rows);
  Normalisation nz;
  nz.in_offset.resize(L.p());
  nz.in_scale.resize(L.p());
  for (int i = 0; i < L.m; ++i) {
    double lo = X.col(L.u_begin() + i).minCoeff(), hi = X.col(L.u_begin() + i).maxCoeff();
    for (int lag = 1; lag < L.nd; ++lag) {
      lo = std::min(lo, X.col(L.u_begin() + lag * L.m + i).minCoeff());
      hi = std::max(hi, X.col(L.u_begin() + lag * L.m + i).maxCoeff());
    }
    // The controller may command anything inside the limits.
    if (size_t(i) < spec.u_lo.size()) lo = std::min(lo, spec.u_lo[size_t(i)]);
    if (size_t(i) < spec.u_hi.size()) hi = std::max(hi, spec.u_hi[size_t(i)]);
    for (int lag = 0; lag < L.nd; ++lag) set_range(nz, L.u_begin() + lag * L.m + i, lo, hi);
  }
  for (int j = 0; j < L.n; ++j) {
    double lo = Y.col(j).minCoeff(), hi = Y.col(j).maxCoeff();
    for (int lag = 0; lag < L.dd; ++lag) {
      lo = std::min(lo, X.col(L.y_begin() + lag * L.n + j).minCoeff());
      hi = std::max(hi, X.col(L.y_begin() + lag * L.n + j).maxCoeff());
    }
    for (int lag = 0; lag < L.dd; ++lag) set_range(nz, L.y_begin() + lag * L.n + j, lo, hi);
  }
  for (int i = 0; i < L.w; ++i)
    set_range(nz, L.l_begin() + i, X.col(L.l_begin() + i).minCoeff(), X.col(L.l_begin() + i).maxCoeff());

  nz.out_offset.resize(L.n);
  nz.out_scale.resize(L.n);
  for (int j = 0; j < L.n; ++j) {
    double dev = 0.0;
    if (spec.residual) {
      nz.out_offset(j) = 0.0;
      dev = (Y.col(j) - X.col(L.y_begin() + j)).cwiseAbs().maxCoeff();
    } else {
      nz.out_offset(j) = size_t(j) < spec.y_neutral.size() ? spec.y_neutral[size_t(j)] : 0.5 * (Y.col(j).minCoeff() + Y.col(j).maxCoeff());
      dev = (Y.col(j).array() - nz.out_offset(j)).abs().maxCoeff();
    }
    nz.out_scale(j) = dev > 0.0 ? spec.out_margin * dev : 1.0;
  }
  return nz;
}

Eigen::MatrixXd normalise_inputs(const Normalisation& nz, const Eigen::MatrixXd& X) {
  return (X.rowwise() - nz.in_offset.transpose()).array().rowwise() * nz.in_scale.transpose().array();
}

std::vector<Fold> time_series_split(long rows, int folds) {
  if (folds < 2) throw PipelineError("a time-series split needs at least 2 folds");
  const long test = rows / (folds + 1);
  if (test < 1) throw PipelineError("too few rows (" + std::to_string(rows) + ") for " + std::to_string(folds) + " folds");
  std::vector<Fold> out;
  for (long start = rows - folds * test; start < rows; start += test) out.push_back({start, start + test});
  return out;
}

Partition partition(long rows, int folds) {
  const std::vector<Fold> f = time_series_split(rows, folds);
  const Fold& test = f.back();
  const Fold& val = f[f.size() - 2];
  return {val.test_begin, val.test_begin, val.test_end, test.test_begin, test.test_end};
}

}  // namespace nlsoft::model
