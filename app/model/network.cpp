#include "app/model/network.hpp"

#include <cmath>

#include "app/model/eigen_blocking.hpp"
#include "app/model/error.hpp"
#include "shared/fixed_math.hpp"

namespace nlsoft::model {
namespace {

// Before any product: see eigen_blocking.hpp.
[[maybe_unused]] const bool kEigenBlockingPinned = pin_eigen_blocking();

using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using ConstMap = Eigen::Map<const RowMat>;
using Map = Eigen::Map<RowMat>;
using ConstRow = Eigen::Map<const Eigen::RowVectorXd>;

double act1(Activation a, double x) {
  switch (a) {
    case Activation::Relu: return x > 0.0 ? x : 0.0;
    case Activation::Tanh: return fixed_math::tanh(x);
    case Activation::Sigmoid: return fixed_math::sigmoid(x);
    case Activation::HardSigmoid: return std::min(1.0, std::max(0.0, 0.2 * x + 0.5));
    case Activation::Linear: break;
  }
  return x;
}

double dact1(Activation a, double x) {
  switch (a) {
    case Activation::Relu: return x > 0.0 ? 1.0 : 0.0;
    case Activation::Tanh: {
      const double t = fixed_math::tanh(x);
      return 1.0 - t * t;
    }
    case Activation::Sigmoid: {
      const double s = fixed_math::sigmoid(x);
      return s * (1.0 - s);
    }
    case Activation::HardSigmoid: return (x > -2.5 && x < 2.5) ? 0.2 : 0.0;
    case Activation::Linear: break;
  }
  return 1.0;
}

// The derivative where the activation's output gives it without a second
// tanh or exp (the costliest part of a small network's backward pass): the
// same bits as dact1, whose 1 - t*t takes the t the forward pass kept.
// Blocks of the caches' columns are taken as they are, not copied.
using ConstRef = Eigen::Ref<const Eigen::MatrixXd>;
Eigen::MatrixXd derivative_from_output(Activation act, const ConstRef& z, const ConstRef& a) {
  switch (act) {
    case Activation::Tanh: return (1.0 - a.array().square()).matrix();
    case Activation::Sigmoid: return (a.array() * (1.0 - a.array())).matrix();
    default: return z.unaryExpr([act](double x) { return dact1(act, x); });
  }
}

// v[0, n) through the activation (Keras definitions, hard_sigmoid =
// clip(0.2 x + 0.5, 0, 1) as shared/activation.hpp), in place: tanh and
// sigmoid on fixed_math's lanes, the same bits as act1 in fewer cycles (a
// GRU's gates were 38 % of a GRU rig's `train --run` on a 10-minute PRBS
// run, which went from 102 to 82 CPU-s with the same model hash).
void activate_in_place(Activation a, double* v, Eigen::Index n) {
  switch (a) {
    case Activation::Tanh: fixed_math::tanh_n(v, v, n); return;
    case Activation::Sigmoid: fixed_math::sigmoid_n(v, v, n); return;
    default:
      for (Eigen::Index i = 0; i < n; ++i) v[i] = act1(a, v[i]);
  }
}

}  // namespace

Network::Network(int inputs, const std::vector<LayerSpec>& specs) : inputs_(inputs) {
  if (specs.empty()) throw PipelineError("a network needs at least one layer");
  uint32_t offset = 0;
  int width = inputs;
  for (const LayerSpec& s : specs) {
    if (s.units < 1) throw PipelineError("every layer needs at least one unit");
    Layer L;
    L.kind = s.kind;
    L.act = s.act;
    L.rec_act = s.rec_act;
    L.reset_after = s.reset_after;
    L.in = static_cast<uint16_t>(width);
    L.out = static_cast<uint16_t>(s.units);
    L.offset = offset;
    offset += layer_weight_count(L);
    layers_.push_back(L);
    width = s.units;
  }
  theta_.assign(offset, 0.0);
}

int Network::outputs() const { return layers_.empty() ? 0 : layers_.back().out; }

void Network::initialise(Random& rng) {
  for (double& t : theta_) t = 0.0;
  for (const Layer& L : layers_) {
    const int cols = layer_columns(L.kind, L.out);
    const double limit = std::sqrt(6.0 / (L.in + cols));
    double* k = theta_.data() + L.offset;
    for (int i = 0; i < L.in * cols; ++i) k[i] = rng.uniform(-limit, limit);
  }
}

// Each layer writes its output straight into the next layer's input (the
// last into out), and a Dense layer's activation is that output: the
// recursion runs this once per window step, where copies and fresh buffers
// cost as much as the layers' arithmetic on networks of a few units.
const Eigen::MatrixXd& Network::forward(const Eigen::MatrixXd& X, Cache& c) const {
  const size_t n = layers_.size();
  c.in.resize(n);
  c.pre.resize(n);
  c.post.resize(n);
  c.in[0] = X;
  for (size_t li = 0; li < n; ++li) {
    const Layer& L = layers_[li];
    const double* w = theta_.data() + L.offset;
    const Eigen::MatrixXd& a = c.in[li];
    Eigen::MatrixXd& next = li + 1 < n ? c.in[li + 1] : c.out;
    if (L.kind == LayerKind::Dense) {
      const ConstMap W(w, L.in, L.out);
      const ConstRow b(w + L.in * L.out, L.out);
      c.pre[li].noalias() = a * W;
      c.pre[li].rowwise() += b;
      next = c.pre[li];
      activate_in_place(L.act, next.data(), next.size());
    } else {
      const int u = L.out, g3 = 3 * u;
      const ConstMap K(w, L.in, g3);
      const double* bias = w + (L.in + u) * g3;
      Eigen::MatrixXd& G = c.pre[li];
      Eigen::MatrixXd& post = c.post[li];
      G.noalias() = a * K;
      G.rowwise() += ConstRow(bias, g3);
      if (L.reset_after) {
        G.leftCols(2 * u).rowwise() += ConstRow(bias + g3, 2 * u);
      }
      // Whole columns of a column-major matrix: each block is one run of
      // memory, as activate_in_place takes it.
      const Eigen::Index rows = G.rows();
      post.resize(rows, g3);
      post.leftCols(2 * u) = G.leftCols(2 * u);
      activate_in_place(L.rec_act, post.data(), rows * 2 * u);
      if (L.reset_after)
        G.rightCols(u) += (post.middleCols(u, u).array().rowwise() * ConstRow(bias + g3 + 2 * u, u).array()).matrix();
      post.rightCols(u) = G.rightCols(u);
      activate_in_place(L.act, post.data() + rows * 2 * u, rows * u);
      next = ((1.0 - post.leftCols(u).array()) * post.rightCols(u).array()).matrix();
    }
  }
  return c.out;
}

Eigen::MatrixXd Network::predict(const Eigen::MatrixXd& X) const {
  Cache c;
  return forward(X, c);
}

void Network::backward(const Cache& c, const Eigen::MatrixXd& dOut, std::vector<double>& grad) const {
  grad.assign(theta_.size(), 0.0);
  backward_add(c, dOut, grad, nullptr);
}

void Network::backward_add(const Cache& c, const Eigen::MatrixXd& dOut, std::vector<double>& grad,
                           Eigen::MatrixXd* dX) const {
  Eigen::MatrixXd d = dOut;
  for (size_t li = layers_.size(); li-- > 0;) {
    const Layer& L = layers_[li];
    const double* w = theta_.data() + L.offset;
    double* g = grad.data() + L.offset;
    const Eigen::MatrixXd& x = c.in[li];
    if (L.kind == LayerKind::Dense) {
      const Eigen::MatrixXd& out = li + 1 < layers_.size() ? c.in[li + 1] : c.out;  // the activation
      const Eigen::MatrixXd dz = (d.array() * derivative_from_output(L.act, c.pre[li], out).array()).matrix();
      Map(g, L.in, L.out) += x.transpose() * dz;
      Eigen::Map<Eigen::RowVectorXd>(g + L.in * L.out, L.out) += dz.colwise().sum();
      if (li > 0 || dX) d = dz * ConstMap(w, L.in, L.out).transpose();
    } else {
      const int u = L.out, g3 = 3 * u;
      const Eigen::MatrixXd& G = c.pre[li];
      const Eigen::MatrixXd& P = c.post[li];
      const auto z = P.leftCols(u).array();
      const auto r = P.middleCols(u, u).array();
      const auto hh = P.rightCols(u).array();
      Eigen::MatrixXd dG(G.rows(), g3);
      // h = (1 - z) h~
      const Eigen::ArrayXXd dhh = d.array() * (1.0 - z);
      const Eigen::ArrayXXd dz = -d.array() * hh;
      dG.rightCols(u) = (dhh * derivative_from_output(L.act, G.rightCols(u), P.rightCols(u)).array()).matrix();
      dG.leftCols(u) = (dz * derivative_from_output(L.rec_act, G.leftCols(u), P.leftCols(u)).array()).matrix();
      const double* bias = w + (L.in + u) * g3;
      double* gbias = g + (L.in + u) * g3;
      if (L.reset_after) {
        const ConstRow rbh(bias + g3 + 2 * u, u);
        const Eigen::ArrayXXd dr = dG.rightCols(u).array().rowwise() * rbh.array();
        dG.middleCols(u, u) =
            (dr * derivative_from_output(L.rec_act, G.middleCols(u, u), P.middleCols(u, u)).array()).matrix();
        Eigen::Map<Eigen::RowVectorXd> grb(gbias + g3, g3);
        grb.head(2 * u) += dG.leftCols(2 * u).colwise().sum();
        grb.tail(u) += (dG.rightCols(u).array() * r).matrix().colwise().sum();
      } else {
        dG.middleCols(u, u).setZero();
      }
      Map(g, L.in, g3) += x.transpose() * dG;
      Eigen::Map<Eigen::RowVectorXd>(gbias, g3) += dG.colwise().sum();
      if (li > 0 || dX) d = dG * ConstMap(w, L.in, g3).transpose();
    }
  }
  if (dX) *dX = std::move(d);
}

}  // namespace nlsoft::model
