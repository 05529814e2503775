// The controller's fast rollout (rollout.hpp) held to the reference
// derivatives (derivatives.hpp: jets through the generic network code, and
// the paper's stencil) on random models and shapes, over every capacity a
// build ships: what a firmware image runs is tested here on the host.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "capacities.hpp"
#include "shared/derivatives.hpp"
#include "shared/kernels.hpp"
#include "support/random_model.hpp"

using namespace nlsoft;

namespace {

struct Case {
  const char* name;
  int m, n, w, N, Nc;
  enum Net { ReluDense, TanhDense, Gru, GruTanh, GruHardSigmoid } net;
  bool residual;
};

// Shapes of the three rigs and odd ones; each capacity runs those it holds.
const Case kCases[] = {
    {"msd", 1, 1, 0, 1, 1, Case::TanhDense, true},
    {"msd-horizon", 1, 1, 0, 40, 2, Case::TanhDense, true},
    {"hasel-relu", 6, 3, 18, 3, 1, Case::ReluDense, false},
    {"hasel-tanh", 6, 3, 18, 4, 1, Case::TanhDense, false},
    {"tendon", 2, 3, 11, 3, 3, Case::Gru, false},
    {"tendon-hard-sigmoid", 2, 3, 11, 4, 2, Case::GruHardSigmoid, false},
    {"residual", 2, 3, 4, 5, 2, Case::GruTanh, true},
    {"wide-dense", 3, 2, 2, 4, 4, Case::TanhDense, true},
};

template <class Cap>
test::OwnedModel<Cap> model_for(const Case& c, unsigned seed) {
  const int h = c.m == 1 ? 4 : 5;
  switch (c.net) {
    case Case::ReluDense:  // the shipped hasel model's layers
      return test::random_model<Cap>(c.m, c.n, c.w, 2,
                                     {{LayerKind::Dense, h, Activation::Relu},
                                      {LayerKind::Dense, h, Activation::Relu},
                                      {LayerKind::Dense, c.n, Activation::Tanh}},
                                     seed, 0.6f, c.residual);
    case Case::TanhDense:
      return test::random_model<Cap>(c.m, c.n, c.w, 2,
                                     {{LayerKind::Dense, h, Activation::Tanh},
                                      {LayerKind::Dense, h, Activation::Sigmoid},
                                      {LayerKind::Dense, c.n, Activation::Tanh}},
                                     seed, 0.6f, c.residual);
    case Case::Gru:
      return test::random_model<Cap>(c.m, c.n, c.w, 2,
                                     {{LayerKind::Gru, 5, Activation::Tanh, Activation::Sigmoid, seed % 2 == 0},
                                      {LayerKind::Dense, 5, Activation::Relu},
                                      {LayerKind::Dense, c.n, Activation::Tanh}},
                                     seed, 0.6f, c.residual);
    case Case::GruTanh:
      return test::random_model<Cap>(c.m, c.n, c.w, 2,
                                     {{LayerKind::Gru, 5, Activation::Tanh, Activation::Sigmoid, seed % 2 == 0},
                                      {LayerKind::Dense, c.n, Activation::Tanh}},
                                     seed, 0.6f, c.residual);
    case Case::GruHardSigmoid:
    default:
      return test::random_model<Cap>(c.m, c.n, c.w, 2,
                                     {{LayerKind::Gru, 5, Activation::Tanh, Activation::HardSigmoid, seed % 2 == 1},
                                      {LayerKind::Dense, c.n, Activation::Linear}},
                                     seed, 0.6f, c.residual);
  }
}

template <class Cap>
bool fits(const Case& c) {
  return c.m <= Cap::m && c.n <= Cap::n && c.w <= Cap::w && c.N <= Cap::N && c.Nc <= Cap::Nc;
}

std::vector<float> random_vec(int count, std::mt19937& rng, float lo, float hi) {
  std::uniform_real_distribution<float> d(lo, hi);
  std::vector<float> v(count);
  for (float& x : v) x = d(rng);
  return v;
}

}  // namespace

template <class Cap>
class FastRollout : public ::testing::Test {
 protected:
  static constexpr int K = Dims<Cap>::K;
  // Runs f(name, seed, N, Nc, model, x0, U) on models of every shape the
  // capacity has a kernel for, with ReLU, tanh and sigmoid layers, and, where
  // it keeps the generic kernel, on the shapes of kCases too.
  template <class F>
  void for_each_case(F f) {
    int ran = 0;
    auto run = [&](const char* name, unsigned seed, int N, int Nc, test::OwnedModel<Cap>& o) {
      ASSERT_EQ(finalize_model(o.model), Status::Ok) << name;
      std::mt19937 rng(seed * 31);
      const auto x0 = random_vec(o.model.p(), rng, -1.0f, 1.0f);
      const auto U = random_vec(Nc * o.model.m, rng, -0.8f, 0.8f);
      f(name, seed, N, Nc, o.model, x0, U);
      ++ran;
    };
    shapes(run, typename Cap::Shapes{});
    if constexpr (Cap::generic) {
      for (const Case& c : kCases) {
        if (!fits<Cap>(c)) continue;
        for (unsigned seed = 1; seed <= 4; ++seed) {
          auto o = model_for<Cap>(c, seed);
          if (check_model_shape(o.model) == Status::TooLarge) continue;
          run(c.name, seed, c.N, c.Nc, o);
        }
      }
    }
    EXPECT_GE(ran, 4) << "too few models to test anything";
  }

  template <class Run, class... Shapes>
  void shapes(Run& run, ShapeList<Shapes...>) {
    (one_shape<Shapes>(run), ...);
  }
  template <class S, class Run>
  void one_shape(Run& run) {
    const int N = Cap::N < 4 ? Cap::N : 4, Nc = Cap::Nc < 2 ? Cap::Nc : 2;
    const Activation hidden[] = {Activation::Relu, Activation::Tanh, Activation::Sigmoid, Activation::Relu};
    const Activation out[] = {Activation::Tanh, Activation::Linear, Activation::Tanh, Activation::Linear};
    for (unsigned seed = 1; seed <= 4; ++seed) {
      auto o = test::ShapeModel<Cap, S>::make(seed, hidden[seed - 1], out[seed - 1], 0.6f, seed == 4);
      run("shipped shape", seed, N, Nc, o);
    }
  }
};
TYPED_TEST_SUITE(FastRollout, test::ShippedCapacities, test::CapacityName);

// Values and Jacobian of the fast kernels equal the generic jets up to the
// fast activations' error (activation.hpp: below 3e-7 per activation).
TYPED_TEST(FastRollout, MatchesTheReferenceJets) {
  using Cap = TypeParam;
  constexpr int kK = Dims<Cap>::K;
  this->for_each_case([&](const char* name, unsigned seed, int N, int Nc, const Model<Cap>& M,
                          const std::vector<float>& x0, const std::vector<float>& U) {
    RolloutKernels<Cap> kern;
    ASSERT_EQ(select_kernels(M, kern), Status::Ok) << name;
    static HorizonDerivatives<Cap> ref;
    static JetScratch<Cap> js;
    derivatives_jets(M, x0.data(), U.data(), N, Nc, ref, js);
    static float Y[Cap::N * Cap::n], G[Cap::N * Cap::n * kK];
    static RolloutScratch<Cap> rs;
    float pre[(Cap::nd + 1) * Cap::width];
    const ConstantInputs ci = kern.constant(M, x0.data(), pre);  // what the solver uses
    // Poison G past the live columns: the kernels must write every entry.
    for (float& g : G) g = NAN;
    kern.jacobian(M, x0.data(), U.data(), N, Nc, ci, Y, G, rs);
    static float Yv[Cap::N * Cap::n];
    kern.values(M, x0.data(), U.data(), N, Nc, ci, Yv, nullptr, rs);
    double gmax = 0;
    for (int r = 0; r < N * M.n; ++r)
      for (int a = 0; a < kK; ++a) gmax = std::max(gmax, double(std::fabs(ref.G[r * kK + a])));
    ASSERT_GT(gmax, 1e-4) << name << ": model too flat to test anything";
    for (int r = 0; r < N * M.n; ++r) {
      const double ytol = 2e-5 * (1.0 + std::fabs(ref.Y[r]));
      EXPECT_NEAR(Y[r], ref.Y[r], ytol) << name << " seed " << seed << " row " << r;
      EXPECT_EQ(Y[r], Yv[r]) << "values alone and values with tangents differ";
      for (int a = 0; a < kK; ++a)
        EXPECT_NEAR(G[r * kK + a], ref.G[r * kK + a], 1e-4 * gmax + 1e-6)
            << name << " seed " << seed << " row " << r << " dir " << a;
    }
  });
}

// The paper's stencil on the generic code agrees with the chain rule.
TYPED_TEST(FastRollout, JetsAgreeWithThePapersStencil) {
  using Cap = TypeParam;
  constexpr int kK = Dims<Cap>::K;
  this->for_each_case([&](const char* name, unsigned seed, int N, int Nc, const Model<Cap>& M,
                          const std::vector<float>& x0, const std::vector<float>& U) {
    // kinks (ReLU, hard sigmoid): a stencil may straddle one
    for (int l = 0; l < M.layer_count; ++l) {
      const Layer& L = M.layer[l];
      const bool gate_kink = L.kind == LayerKind::Gru && L.rec_act == Activation::HardSigmoid;
      if (L.act == Activation::Relu || L.act == Activation::HardSigmoid || gate_kink) return;
    }
    static HorizonDerivatives<Cap> ex, fd;
    static JetScratch<Cap> js;
    static StencilScratch<Cap> ss;
    derivatives_jets(M, x0.data(), U.data(), N, Nc, ex, js);
    derivatives_stencil(M, x0.data(), U.data(), N, Nc, 2e-2f, fd, ss);
    double gmax = 0;
    for (int r = 0; r < N * M.n; ++r) {
      EXPECT_FLOAT_EQ(ex.Y[r], fd.Y[r]);
      for (int a = 0; a < kK; ++a) gmax = std::max(gmax, double(std::fabs(ex.G[r * kK + a])));
    }
    // stencil error O(eps^2) relative, plus float rounding of Y / eps
    const double gtol = 1e-2 * gmax + 2e-5;
    for (int r = 0; r < N * M.n; ++r)
      for (int a = 0; a < kK; ++a)
        EXPECT_NEAR(ex.G[r * kK + a], fd.G[r * kK + a], gtol) << name << " seed " << seed << " row " << r;
    // Past the control horizon U is held: with Nc < N the last row still
    // moves every later prediction, so its derivative must not vanish.
    if (Nc < N) {
      double last = 0;
      for (int i = 0; i < M.n; ++i)
        for (int a = (Nc - 1) * M.m; a < Nc * M.m; ++a) last += std::fabs(ex.G[((N - 1) * M.n + i) * kK + a]);
      EXPECT_GT(last, 0.0);
    }
  });
}

TEST(ReferenceJets, MatchDoublePrecisionStencil) {
  // The float model evaluated at U +- h; a generous h where float rounding is
  // negligible and the O(h^4) error of a fourth-order stencil is below the tolerance.
  using Cap = HostCapacity;
  constexpr int kK = Dims<Cap>::K;
  auto o = test::random_model<Cap>(2, 3, 3, 2,
                                   {{LayerKind::Dense, 8, Activation::Tanh}, {LayerKind::Dense, 3, Activation::Linear}},
                                   11, 0.5f);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  std::mt19937 rng(5);
  const auto x0 = random_vec(o.model.p(), rng, -1.0f, 1.0f);
  std::vector<float> U = random_vec(4, rng, -0.5f, 0.5f);
  static HorizonDerivatives<Cap> ex;
  static JetScratch<Cap> es;
  derivatives_jets(o.model, x0.data(), U.data(), 3, 2, ex, es);
  static HorizonScratch<Cap, float> hs;
  const float h = 1e-2f;
  for (int a = 0; a < 4; ++a) {
    float Yp[9], Ym[9], Yp2[9], Ym2[9];
    auto roll = [&](float du, float* Y) {
      std::vector<float> V = U;
      V[a] += du;
      predict_horizon(o.model, x0.data(), V.data(), 3, 2, Y, hs);
    };
    roll(h, Yp), roll(-h, Ym), roll(2 * h, Yp2), roll(-2 * h, Ym2);
    for (int r = 0; r < 9; ++r) {
      // fourth-order stencil: (-f(2h) + 8f(h) - 8f(-h) + f(-2h)) / 12h
      const double d = (-double(Yp2[r]) + 8.0 * Yp[r] - 8.0 * Ym[r] + double(Ym2[r])) / (12.0 * h);
      EXPECT_NEAR(ex.G[r * kK + a], d, 2e-4) << "row " << r << " dir " << a;
    }
  }
}
