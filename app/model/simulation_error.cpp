#include "app/model/simulation_error.hpp"

#include <cmath>
#include <limits>

namespace nlsoft::model {
namespace {

// The recursion for windows of equal length, batched: row b of every matrix
// is window b. With `grad`, keeps each step's activations and carries
// d loss / d y^(t) back through the y-history columns (every lag that step
// fills later) and, for a residual model, through the y(k) it adds.
double run_windows(const Network& net, const SimulationData& s, const long* starts, long B, int H,
                   std::vector<double>* grad) {
  const InputLayout& L = s.layout;
  const int n = L.n, hist = L.dd * n, yb = L.y_begin(), p = L.p();
  Eigen::MatrixXd yq(B, hist), X(B, p), yhat(B, n), next(B, hist);
  for (long b = 0; b < B; ++b) yq.row(b) = s.Xn.block(starts[b], yb, 1, hist);
  // Kept between calls: the same shapes come back every evaluation, and
  // fresh buffers would cost a page fault per page each time.
  thread_local std::vector<Network::Cache> caches;
  if (caches.size() < (grad ? size_t(H) : 1)) caches.resize(grad ? size_t(H) : 1);
  std::vector<Eigen::MatrixXd> dy(grad ? size_t(H) : 0);  // d loss / d y^(t), physical units
  const double count = double(B) * H * n;
  const auto y_phys = [&](const Eigen::MatrixXd& cols) {  // normalised y columns -> physical
    return ((cols.array().rowwise() / s.y_in_scale.transpose().array()).rowwise() + s.y_in_offset.transpose().array())
        .matrix();
  };
  double loss = 0.0;
  for (int t = 0; t < H; ++t) {
    for (long b = 0; b < B; ++b) X.row(b) = s.Xn.row(starts[b] + t);
    X.middleCols(yb, hist) = yq;
    Network::Cache& c = caches[grad ? size_t(t) : 0];
    const Eigen::MatrixXd& out = net.forward(X, c);
    yhat = (out.array().rowwise() * s.out_scale.transpose().array()).rowwise() + s.out_offset.transpose().array();
    if (s.residual) yhat += y_phys(yq.leftCols(n));
    Eigen::MatrixXd e(B, n);
    for (long b = 0; b < B; ++b) e.row(b) = yhat.row(b) - s.Y.row(starts[b] + t);
    const Eigen::MatrixXd we = (e.array().rowwise() * s.weight.transpose().array()).matrix();
    loss += (we.array() * e.array()).sum();
    if (grad) dy[size_t(t)] = (2.0 / count) * we;
    if (hist > n) next.rightCols(hist - n) = yq.leftCols(hist - n);
    next.leftCols(n) = ((yhat.rowwise() - s.y_in_offset.transpose()).array().rowwise() * s.y_in_scale.transpose().array())
                           .matrix();
    yq.swap(next);
  }
  loss /= count;
  if (!grad || !std::isfinite(loss)) return loss;
  Eigen::MatrixXd dX;
  for (int t = H - 1; t >= 0; --t) {
    const Eigen::MatrixXd& dY = dy[size_t(t)];
    const Eigen::MatrixXd dOut = (dY.array().rowwise() * s.out_scale.transpose().array()).matrix();
    net.backward_add(caches[size_t(t)], dOut, *grad, &dX);
    // Lag l of the y history at step t is y^(t - 1 - l); the measured
    // history before the window takes no gradient.
    for (int l = 0; l < L.dd && t - 1 - l >= 0; ++l)
      dy[size_t(t - 1 - l)] += (dX.middleCols(yb + l * n, n).array().rowwise() * s.y_in_scale.transpose().array()).matrix();
    if (s.residual && t >= 1) dy[size_t(t - 1)] += dY;
  }
  return loss;
}

}  // namespace

double simulation_loss(const Network& net, const SimulationData& s, const std::vector<long>& starts, int H,
                       std::vector<double>* grad) {
  if (starts.empty() || H < 1) return 0.0;
  return run_windows(net, s, starts.data(), long(starts.size()), H, grad);
}

double free_run_loss(const Network& net, const SimulationData& s, const std::vector<RowRange>& pieces) {
  double sum = 0.0;
  long rows = 0;
  for (const RowRange& r : pieces) {
    const long len = r.end - r.begin;
    if (len <= 0) continue;
    const double l = run_windows(net, s, &r.begin, 1, int(len), nullptr);
    if (!std::isfinite(l)) return std::numeric_limits<double>::infinity();
    sum += l * double(len);
    rows += len;
  }
  return rows > 0 ? sum / double(rows) : std::numeric_limits<double>::infinity();
}

std::vector<long> window_starts(const std::vector<RowRange>& pieces, int H, int stride, int offset) {
  std::vector<long> out;
  for (const RowRange& r : pieces)
    for (long b = r.begin + offset; b + H <= r.end; b += stride) out.push_back(b);
  return out;
}

}  // namespace nlsoft::model
