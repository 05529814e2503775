// The two derivative modes held against each other, and the exact mode held
// against a double-precision stencil of the float model.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "shared/derivatives.hpp"
#include "support/random_model.hpp"

using namespace nlsoft;
using Cap = HostCapacity;
constexpr int K = Derived<Cap>::K;

namespace {

struct Case {
  int m, n, w, N, Nc;
  bool gru;
  bool residual;
};

std::vector<float> random_vec(int count, std::mt19937& rng, float lo, float hi) {
  std::uniform_real_distribution<float> d(lo, hi);
  std::vector<float> v(count);
  for (float& x : v) x = d(rng);
  return v;
}

}  // namespace

class ModesAgree : public ::testing::TestWithParam<Case> {};

TEST_P(ModesAgree, JacobianAndCurvatureOnRandomModels) {
  const Case c = GetParam();
  for (unsigned seed = 1; seed <= 5; ++seed) {
    auto o = c.gru ? test::random_model<Cap>(c.m, c.n, c.w, 2,
                                             {{LayerKind::Gru, 5, Activation::Tanh, Activation::Sigmoid, seed % 2 == 0},
                                              {LayerKind::Dense, 5, Activation::Tanh},
                                              {LayerKind::Dense, c.n, Activation::Tanh}},
                                             seed, 0.6f, c.residual)
                   : test::random_model<Cap>(c.m, c.n, c.w, 2,
                                             {{LayerKind::Dense, 6, Activation::Tanh},
                                              {LayerKind::Dense, 5, Activation::Sigmoid},
                                              {LayerKind::Dense, c.n, Activation::Tanh}},
                                             seed, 0.6f, c.residual);
    ASSERT_EQ(finalize_model(o.model), Status::Ok);
    std::mt19937 rng(seed * 31);
    const auto x0 = random_vec(o.model.p(), rng, -1.0f, 1.0f);
    const auto U = random_vec(c.Nc * c.m, rng, -0.8f, 0.8f);

    static HorizonDerivatives<Cap> ex, fd;
    static ExactScratch<Cap> es;
    static FdScratch<Cap> fs;
    derivatives_exact(o.model, x0.data(), U.data(), c.N, c.Nc, ex, es);
    derivatives_fd(o.model, x0.data(), U.data(), c.N, c.Nc, 2e-2f, fd, fs);

    const int k = c.Nc * c.m;
    double gmax = 0, hmax = 0;
    for (int r = 0; r < c.N * c.n; ++r) {
      EXPECT_FLOAT_EQ(ex.Y[r], fd.Y[r]);
      for (int a = 0; a < k; ++a) {
        gmax = std::max(gmax, double(std::fabs(ex.G[r * K + a])));
        hmax = std::max(hmax, double(std::fabs(ex.D2[r * K + a])));
      }
    }
    ASSERT_GT(gmax, 1e-4) << "model too flat to test anything";
    // stencil error O(eps^2) relative, plus float rounding of Y / eps (^2)
    const double gtol = 1e-2 * gmax + 2e-5, htol = 3e-2 * std::max(hmax, gmax) + 2e-3;
    for (int r = 0; r < c.N * c.n; ++r)
      for (int a = 0; a < k; ++a) {
        EXPECT_NEAR(ex.G[r * K + a], fd.G[r * K + a], gtol) << "seed " << seed << " row " << r << " dir " << a;
        EXPECT_NEAR(ex.D2[r * K + a], fd.D2[r * K + a], htol) << "seed " << seed << " row " << r << " dir " << a;
      }
    // Past the control horizon U is held: with Nc < N the last row still
    // moves every later prediction, so its derivative must not vanish.
    if (c.Nc < c.N) {
      double last = 0;
      for (int i = 0; i < c.n; ++i)
        for (int a = (c.Nc - 1) * c.m; a < k; ++a) last += std::fabs(ex.G[((c.N - 1) * c.n + i) * K + a]);
      EXPECT_GT(last, 0.0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, ModesAgree,
                         ::testing::Values(Case{1, 1, 0, 1, 1, false, false},   // msd-like
                                           Case{6, 3, 18, 3, 1, false, false},  // hasel
                                           Case{2, 3, 11, 3, 3, true, false},   // tendon
                                           Case{2, 3, 4, 5, 2, true, true},     // residual, Nc < N
                                           Case{3, 2, 2, 4, 4, false, true}));

TEST(ExactDerivatives, MatchDoublePrecisionStencil) {
  // The float model evaluated at U +- h in double arithmetic on the input
  // side is still float inside; use a generous h where float rounding is
  // negligible and the O(h^2) error is below the tolerance.
  auto o = test::random_model<Cap>(2, 3, 3, 2,
                                   {{LayerKind::Dense, 8, Activation::Tanh}, {LayerKind::Dense, 3, Activation::Linear}},
                                   11, 0.5f);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  std::mt19937 rng(5);
  const auto x0 = random_vec(o.model.p(), rng, -1.0f, 1.0f);
  std::vector<float> U = random_vec(4, rng, -0.5f, 0.5f);
  static HorizonDerivatives<Cap> ex;
  static ExactScratch<Cap> es;
  derivatives_exact(o.model, x0.data(), U.data(), 3, 2, ex, es);
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
      EXPECT_NEAR(ex.G[r * K + a], d, 2e-4) << "row " << r << " dir " << a;
    }
  }
}
