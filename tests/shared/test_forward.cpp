// Layers against values computed by hand or by an independent double
// precision implementation of the Keras formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "shared/forward.hpp"
#include "support/rig_capacities.hpp"
#include "support/random_model.hpp"

using namespace nlsoft;

TEST(Dense, MatchesHandComputedValues) {
  // x = [1, 2], W = [[1, -1], [0.5, 2]] stored [in][out], b = [0.1, -0.2]
  // x W + b = [1 + 1 + 0.1, -1 + 4 - 0.2] = [2.1, 2.8]
  const float W[] = {1.0f, -1.0f, 0.5f, 2.0f, 0.1f, -0.2f};
  const float x[] = {1.0f, 2.0f};
  float y[2];
  Layer L{LayerKind::Dense, Activation::Linear, Activation::Sigmoid, false, 2, 2, 0};
  dense(L, W, x, y);
  EXPECT_FLOAT_EQ(y[0], 2.1f);
  EXPECT_FLOAT_EQ(y[1], 2.8f);
  L.act = Activation::Relu;
  const float xn[] = {-1.0f, 0.0f};  // x W + b = [-0.9, 0.8]
  dense(L, W, xn, y);
  EXPECT_FLOAT_EQ(y[0], 0.0f);
  EXPECT_FLOAT_EQ(y[1], 0.8f);
  L.act = Activation::Tanh;
  dense(L, W, x, y);
  EXPECT_NEAR(y[0], std::tanh(2.1), 1e-6);
}

TEST(Activation, KerasDefinitions) {
  EXPECT_FLOAT_EQ(activate(Activation::HardSigmoid, 0.0f), 0.5f);
  EXPECT_FLOAT_EQ(activate(Activation::HardSigmoid, 1.0f), 0.7f);
  EXPECT_FLOAT_EQ(activate(Activation::HardSigmoid, 3.0f), 1.0f);
  EXPECT_FLOAT_EQ(activate(Activation::HardSigmoid, -2.6f), 0.0f);
  EXPECT_NEAR(activate(Activation::Sigmoid, 0.3f), 1.0 / (1.0 + std::exp(-0.3)), 1e-7);
  // derivatives against central differences in double
  for (Activation a : {Activation::Tanh, Activation::Sigmoid}) {
    for (float x : {-1.7f, -0.2f, 0.4f, 2.2f}) {
      const ActValue v = activate_d2(a, x);
      const double h = 1e-3;
      auto f = [&](double t) { return a == Activation::Tanh ? std::tanh(t) : 1.0 / (1.0 + std::exp(-t)); };
      EXPECT_NEAR(v.df, (f(x + h) - f(x - h)) / (2 * h), 1e-5);
      EXPECT_NEAR(v.d2f, (f(x + h) - 2 * f(x) + f(x - h)) / (h * h), 1e-4);
    }
  }
}

namespace {

double act_d(Activation a, double x) {
  switch (a) {
    case Activation::Tanh: return std::tanh(x);
    case Activation::Sigmoid: return 1.0 / (1.0 + std::exp(-x));
    case Activation::HardSigmoid: return std::min(1.0, std::max(0.0, 0.2 * x + 0.5));
    case Activation::Relu: return x > 0 ? x : 0;
    default: return x;
  }
}

// Keras GRUCell, written from its documentation with explicit per-gate
// matrices, in double.
std::vector<double> keras_gru(int in, int u, const std::vector<float>& Wflat, bool reset_after, Activation act,
                              Activation rec, const std::vector<double>& x, const std::vector<double>& h) {
  const int g3 = 3 * u;
  auto K = [&](int i, int gate, int j) { return double(Wflat[i * g3 + gate * u + j]); };
  auto R = [&](int i, int gate, int j) { return double(Wflat[in * g3 + i * g3 + gate * u + j]); };
  const int b0 = in * g3 + u * g3;
  auto Bi = [&](int gate, int j) { return double(Wflat[b0 + gate * u + j]); };
  auto Br = [&](int gate, int j) { return reset_after ? double(Wflat[b0 + g3 + gate * u + j]) : 0.0; };
  std::vector<double> out(u);
  std::vector<double> z(u), r(u);
  for (int j = 0; j < u; ++j) {
    double az = Bi(0, j) + Br(0, j), ar = Bi(1, j) + Br(1, j);
    for (int i = 0; i < in; ++i) az += x[i] * K(i, 0, j), ar += x[i] * K(i, 1, j);
    for (int i = 0; i < u; ++i) az += h[i] * R(i, 0, j), ar += h[i] * R(i, 1, j);
    z[j] = act_d(rec, az);
    r[j] = act_d(rec, ar);
  }
  for (int j = 0; j < u; ++j) {
    double xh = Bi(2, j);
    for (int i = 0; i < in; ++i) xh += x[i] * K(i, 2, j);
    double rh = 0;
    if (reset_after) {
      double hh = Br(2, j);
      for (int i = 0; i < u; ++i) hh += h[i] * R(i, 2, j);
      rh = r[j] * hh;
    } else {
      for (int i = 0; i < u; ++i) rh += r[i] * h[i] * R(i, 2, j);
    }
    const double cand = act_d(act, xh + rh);
    out[j] = z[j] * h[j] + (1 - z[j]) * cand;
  }
  return out;
}

}  // namespace

class GruCell : public ::testing::TestWithParam<std::tuple<bool, Activation>> {};

TEST_P(GruCell, MatchesKerasFormulasWithNonZeroState) {
  const bool reset_after = std::get<0>(GetParam());
  const Activation rec = std::get<1>(GetParam());
  const int in = 4, u = 3;
  Layer L{LayerKind::Gru, Activation::Tanh, rec, reset_after, uint16_t(in), uint16_t(u), 0};
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> d(-1.0f, 1.0f);
  std::vector<float> W(layer_weight_count(L));
  for (float& v : W) v = d(rng);
  std::vector<double> xd(in), hd(u);
  float x[4], h[3], out[3], gates[9];
  for (int i = 0; i < in; ++i) x[i] = d(rng), xd[i] = x[i];
  for (int i = 0; i < u; ++i) h[i] = d(rng), hd[i] = h[i];
  gru(L, W.data(), x, h, out, gates);
  const auto ref = keras_gru(in, u, W, reset_after, Activation::Tanh, rec, xd, hd);
  for (int j = 0; j < u; ++j) EXPECT_NEAR(out[j], ref[j], 1e-6) << "unit " << j;

  // zero state (nullptr) equals an explicit zero vector
  const float hz[3] = {0, 0, 0};
  float a[3], b[3];
  gru(L, W.data(), x, nullptr, a, gates);
  gru(L, W.data(), x, hz, b, gates);
  for (int j = 0; j < u; ++j) EXPECT_FLOAT_EQ(a[j], b[j]);
}

INSTANTIATE_TEST_SUITE_P(AllVariants, GruCell,
                         ::testing::Combine(::testing::Bool(),
                                            ::testing::Values(Activation::Sigmoid, Activation::HardSigmoid)));

TEST(GruCell, RecurrentKernelIsNotReadTransposed) {
  // A recurrent kernel with a single non-zero entry R[0][z-gate col 1]: only
  // unit 1's update gate may see h[0]. A transposed read would move it to unit 0.
  const int in = 1, u = 2;
  Layer L{LayerKind::Gru, Activation::Tanh, Activation::Sigmoid, false, uint16_t(in), uint16_t(u), 0};
  std::vector<float> W(layer_weight_count(L), 0.0f);
  W[in * 6 + 0 * 6 + 0 * u + 1] = 5.0f;  // recurrent[row 0][gate z, unit 1]
  const float x[1] = {0.0f}, h[2] = {1.0f, 0.0f};
  float out[2], gates[6];
  gru(L, W.data(), x, h, out, gates);
  // unit 0: z = 0.5 -> h = 0.5*1 + 0.5*tanh(0) = 0.5
  // unit 1: z = sigmoid(5), h_prev = 0 -> 0
  EXPECT_NEAR(out[0], 0.5f, 1e-6);
  EXPECT_NEAR(out[1], 0.0f, 1e-6);
}

TEST(Forward, AppliesNormalisationAndResidual) {
  auto o = test::random_model<HostCapacity>(1, 1, 0, 2, {{LayerKind::Dense, 1, Activation::Linear}}, 3);
  Model<HostCapacity>& M = o.model;
  ASSERT_EQ(finalize_model(M), Status::Ok);
  // Replace weights by a known linear map: y_net = sum(x_net) + 0.5
  float* p = o.params.data();
  for (int i = 0; i < 4; ++i) p[i] = 1.0f, p[4 + i] = 2.0f;  // off 1, scale 2
  p[8] = 10.0f, p[9] = 3.0f;                                   // out off 10, scale 3
  for (int i = 0; i < 4; ++i) p[10 + i] = 1.0f;
  p[14] = 0.5f;
  const float x[4] = {1.5f, 2.0f, 0.0f, 1.0f};
  // x_net = [1, 2, -2, 0] -> y_net = 1 + 0.5 = 1.5 -> y = 1.5 * 3 + 10 = 14.5
  ForwardScratch<HostCapacity, float> s;
  float y;
  forward(M, x, &y, s);
  EXPECT_FLOAT_EQ(y, 14.5f);
  M.residual = true;  // adds y(k) = x[nd*m] = x[2] = 0
  const float x2[4] = {1.5f, 2.0f, 4.0f, 1.0f};  // x_net[2] = 6 -> y_net = 9.5 -> y = 38.5 + 4
  forward(M, x2, &y, s);
  EXPECT_FLOAT_EQ(y, 42.5f);
}

TEST(Forward, RejectsShapesBeyondCapacityOrInconsistent) {
  auto o = test::random_model<HaselCapacity>(6, 3, 18, 2,
                                             {{LayerKind::Dense, 5, Activation::Relu},
                                              {LayerKind::Dense, 5, Activation::Relu},
                                              {LayerKind::Dense, 3, Activation::Tanh}},
                                             1);
  EXPECT_EQ(finalize_model(o.model), Status::Ok);
  EXPECT_EQ(o.model.param_count, 233u + o.model.norm_count());  // the paper's 233 parameters
  o.model.layer[1].in = 4;
  EXPECT_EQ(finalize_model(o.model), Status::Inconsistent);
  o.model.layer[1].in = 5;
  o.params[o.params.size() - 1] = std::nanf("");
  EXPECT_EQ(finalize_model(o.model), Status::NotFinite);
  auto big = test::random_model<HaselCapacity>(6, 3, 18, 2, {{LayerKind::Dense, 40, Activation::Relu}}, 1);
  EXPECT_EQ(finalize_model(big.model), Status::TooLarge);
}
