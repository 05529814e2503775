#include "app/model/linear_start.hpp"

#include <algorithm>

#include "app/model/error.hpp"

namespace nlsoft::model {

bool holds_linear_model(const std::vector<LayerSpec>& layers, int n) {
  if (layers.empty() || layers.back().kind != LayerKind::Dense || layers.back().units != n ||
      layers.back().act != Activation::Linear)
    return false;
  for (size_t i = 0; i + 1 < layers.size(); ++i) {
    const LayerSpec& l = layers[i];
    if (l.kind != LayerKind::Dense || l.units < n) return false;
    if (l.act != Activation::Relu && l.act != Activation::Linear) return false;
  }
  return true;
}

void embed_linear_model(Network& net, const Network& linear, const Eigen::MatrixXd& X) {
  const std::vector<Layer>& layers = net.layers();
  if (linear.layers().size() != 1 || linear.layers()[0].act != Activation::Linear)
    throw PipelineError("the start model must be a single linear layer");
  const Layer& s = linear.layers()[0];
  const int p = s.in, n = s.out;
  std::vector<LayerSpec> specs;
  for (const Layer& l : layers) specs.push_back({l.kind, int(l.out), l.act});
  if (net.inputs() != p || !holds_linear_model(specs, n) || X.cols() != p)
    throw PipelineError("the network cannot hold the linear model unchanged");
  const double* ws = linear.theta().data();
  Eigen::MatrixXd W(p, n);
  for (int i = 0; i < p; ++i)
    for (int j = 0; j < n; ++j) W(i, j) = ws[i * n + j];
  // The carried units' shift: each stays above zero over the rows by half
  // its range, so training can move the map without switching them off.
  Eigen::VectorXd shift(n);
  for (int j = 0; j < n; ++j) {
    const Eigen::VectorXd z = X * W.col(j);
    const double lo = (X.rows() > 0 ? z.minCoeff() : 0.0) + ws[p * n + j];
    const double hi = (X.rows() > 0 ? z.maxCoeff() : 0.0) + ws[p * n + j];
    shift(j) = std::max(0.0, -lo) + 0.5 * (hi - lo) + 0.1;
  }
  std::vector<double>& th = net.theta();
  for (size_t li = 0; li < layers.size(); ++li) {
    const Layer& L = layers[li];
    double* w = th.data() + L.offset;
    double* bias = w + L.in * L.out;
    const bool first = li == 0, last = li + 1 == layers.size();
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < L.in; ++i) w[i * L.out + j] = first ? ws[i * n + j] : (i == j ? 1.0 : 0.0);
      bias[j] = first ? ws[p * n + j] + shift(j) : (last ? -shift(j) : 0.0);
    }
    if (first) continue;
    for (int j = n; j < L.out; ++j) bias[j] = 0.0;
    // Nothing out of the previous layer's extra units yet.
    for (int i = n; i < L.in; ++i)
      for (int j = 0; j < L.out; ++j) w[i * L.out + j] = 0.0;
  }
}

}  // namespace nlsoft::model
