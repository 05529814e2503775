// Newton-Raphson on problems whose optimum is known.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "shared/horizon.hpp"
#include "shared/newton.hpp"
#include "capacities.hpp"
#include "support/random_model.hpp"

using namespace nlsoft;
using Cap = HostCapacity;

namespace {

template <class C>
RolloutKernels<C> kernels_of(const Model<C>& M) {
  RolloutKernels<C> k;
  EXPECT_EQ(select_kernels(M, k), Status::Ok);
  return k;
}

template <class C>
Params<C> base_params(int m, int n, int N, int Nc) {
  Params<C> P;
  for (int i = 0; i < n; ++i) P.Q[i] = 1.0f + float(i);
  for (int i = 0; i < m; ++i) P.Lambda[i] = 0.0f, P.u_min[i] = -5.0f, P.u_max[i] = 5.0f;
  P.s = 0.0f, P.b = 0.0f, P.r = 100.0f;
  P.N = uint8_t(N), P.N1 = 1, P.Nc = uint8_t(Nc);
  P.nr_tol = 1e-4f, P.nr_max_iter = 3;
  return P;
}

}  // namespace

TEST(Newton, AffineModelQuadraticCostSolvedExactly) {
  // y = A u + c: the cost is quadratic, U* = (A'QA + Lambda)^-1 (A'Q(r - c) + Lambda u_prev)
  const int m = 2, n = 2;
  auto o = test::random_model<Cap>(m, n, 1, 2, {{LayerKind::Dense, n, Activation::Linear}}, 4, 0.8f);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  std::vector<float> x0 = {0.3f, -0.2f, 0.1f, 0.0f, 0.5f, 0.4f, -0.3f, 0.2f, 0.7f};
  ASSERT_EQ(int(x0.size()), o.model.p());
  static HorizonScratch<Cap, float> hs;
  auto y_of = [&](Eigen::Vector2d u) {
    float U[2] = {float(u(0)), float(u(1))}, Y[2];
    predict_horizon(o.model, x0.data(), U, 1, 1, Y, hs);
    return Eigen::Vector2d(Y[0], Y[1]);
  };
  const Eigen::Vector2d c = y_of({0, 0});
  Eigen::Matrix2d A;
  A.col(0) = y_of({1, 0}) - c;
  A.col(1) = y_of({0, 1}) - c;
  auto P = base_params<Cap>(m, n, 1, 1);
  P.Lambda[0] = 0.3f, P.Lambda[1] = 0.7f;
  const Eigen::Vector2d r(0.4, -0.6), uprev(x0[0], x0[1]);
  const Eigen::Matrix2d Q = Eigen::Vector2d(P.Q[0], P.Q[1]).asDiagonal();
  const Eigen::Matrix2d L = Eigen::Vector2d(P.Lambda[0], P.Lambda[1]).asDiagonal();
  const Eigen::Vector2d Ustar = (A.transpose() * Q * A + L).lu().solve(A.transpose() * Q * (r - c) + L * uprev);

  P.eps = 1e-2f;  // exact for an affine model; smaller steps only add rounding
  for (DerivMode mode : {DerivMode::Exact, DerivMode::Fd}) {
    P.mode = mode;
    float U[2] = {0.0f, 0.0f};
    const float ref[2] = {float(r(0)), float(r(1))};
    static SolverScratch<Cap> s;
    SolverState st;
    const NewtonResult res = newton_solve(o.model, kernels_of(o.model), P, x0.data(), ref, U, st, s);
    EXPECT_TRUE(res.flags & kConverged);
    // every step is damped a little (SolverState::kMuStart): the first
    // lands within 1e-3 of the optimum, the next within rounding
    EXPECT_LE(res.iterations, 3);
    EXPECT_NEAR(U[0], Ustar(0), 1e-4);
    EXPECT_NEAR(U[1], Ustar(1), 1e-4);
    EXPECT_FALSE(res.flags & (kSingular | kNonFinite));
  }
}

// From a warm start (the loop's situation: the previous step's U), Newton is
// quadratic: errors of 1e-2 shrink to 1e-4 and below within three
// iterations, on every capacity a build ships.
template <class C>
class NewtonOnCapacity : public ::testing::Test {};
TYPED_TEST_SUITE(NewtonOnCapacity, test::ShippedCapacities, test::CapacityName);

TYPED_TEST(NewtonOnCapacity, NonlinearReachableTargetConvergesInThreeIterations) {
  using C = TypeParam;
  using S = typename test::FirstShape<typename C::Shapes>::type;  // what the image runs
  const int m = S::m, n = S::n;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    auto o = test::ShapeModel<C, S>::make(seed, Activation::Tanh, Activation::Tanh, 0.7f);
    ASSERT_EQ(finalize_model(o.model), Status::Ok);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> d(-0.5f, 0.5f), small(-0.01f, 0.01f);
    std::vector<float> x0(o.model.p());
    for (float& v : x0) v = d(rng);
    float ustar[C::m], ref[C::n];
    for (int i = 0; i < m; ++i) ustar[i] = d(rng);
    static HorizonScratch<C, float> hs;
    predict_horizon(o.model, x0.data(), ustar, 1, 1, ref, hs);
    auto P = base_params<C>(m, n, 1, 1);
    for (DerivMode mode : {DerivMode::Exact, DerivMode::Fd}) {
      P.mode = mode;
      P.eps = 1e-2f;
      float U[C::m], V[C::m];
      for (int i = 0; i < m; ++i) U[i] = V[i] = ustar[i] + small(rng);
      static SolverScratch<C> s;
      SolverState st;
      P.nr_max_iter = 3;
      NewtonResult res = newton_solve(o.model, kernels_of(o.model), P, x0.data(), ref, U, st, s);
      EXPECT_LE(res.iterations, 3);
      // With more inputs than outputs the optimum is a set: check the
      // outputs, which every point of it reaches.
      if (m <= n) {
        for (int i = 0; i < m; ++i) EXPECT_NEAR(U[i], ustar[i], 1e-4) << "seed " << seed << " mode " << int(mode);
      }
      for (int i = 0; i < n; ++i) EXPECT_NEAR(res.y_hat[i], ref[i], 1e-4) << "seed " << seed << " mode " << int(mode);
      // and the solver sees it: the step it would take next is below the tolerance
      P.nr_max_iter = 10;
      SolverState fresh;
      res = newton_solve(o.model, kernels_of(o.model), P, x0.data(), ref, V, fresh, s);
      EXPECT_TRUE(res.flags & kConverged) << "seed " << seed << " mode " << int(mode) << " step " << res.step;
      EXPECT_LE(res.iterations, 4);
    }
  }
}

// Both modes solve the same Gauss-Newton system and differ only in how G is
// obtained: from the same point they take the same step.
TYPED_TEST(NewtonOnCapacity, ExactAndFdTakeTheSameStep) {
  using C = TypeParam;
  using S = typename test::FirstShape<typename C::Shapes>::type;
  const int m = S::m, n = S::n;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    auto o = test::ShapeModel<C, S>::make(seed, Activation::Tanh, Activation::Tanh, 0.7f);
    ASSERT_EQ(finalize_model(o.model), Status::Ok);
    std::mt19937 rng(seed + 100);
    std::uniform_real_distribution<float> d(-0.5f, 0.5f);
    std::vector<float> x0(o.model.p());
    for (float& v : x0) v = d(rng);
    float ref[C::n];
    for (int i = 0; i < n; ++i) ref[i] = d(rng);
    auto P = base_params<C>(m, n, 1, 1);
    for (int i = 0; i < m; ++i) P.Lambda[i] = 0.1f;  // well posed with more inputs than outputs
    P.nr_max_iter = 1;
    P.eps = 1e-3f;
    float Ue[C::m] = {}, Uf[C::m] = {};
    static SolverScratch<C> s;
    SolverState se, sf;
    P.mode = DerivMode::Exact;
    newton_solve(o.model, kernels_of(o.model), P, x0.data(), ref, Ue, se, s);
    P.mode = DerivMode::Fd;
    newton_solve(o.model, kernels_of(o.model), P, x0.data(), ref, Uf, sf, s);
    for (int i = 0; i < m; ++i) EXPECT_NEAR(Ue[i], Uf[i], 2e-3 * (1.0f + std::fabs(Ue[i]))) << "seed " << seed;
  }
}

// An image refuses a model of a shape it has no kernel for, and changes nothing.
TYPED_TEST(NewtonOnCapacity, ShapesWithoutAKernelAreRefusedUnlessGeneric) {
  using C = TypeParam;
  using S = typename test::FirstShape<typename C::Shapes>::type;
  // the first shape with one unit more in its first layer
  auto o = test::random_model<C>(S::m, S::n, S::w, S::nd, {{LayerKind::Dense, 2, Activation::Tanh},
                                                           {LayerKind::Dense, S::n, Activation::Linear}}, 3);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  RolloutKernels<C> k;
  EXPECT_EQ(select_kernels(o.model, k), C::generic ? Status::Ok : Status::Unsupported);
  if (!C::generic) {
    EXPECT_EQ(k.values, nullptr);
  }
  auto shaped = test::ShapeModel<C, S>::make(1, Activation::Relu, Activation::Tanh);
  ASSERT_EQ(finalize_model(shaped.model), Status::Ok);
  EXPECT_EQ(select_kernels(shaped.model, k), Status::Ok);
}

// A shape that fixes its layers' activations (an image without model
// uploads) has no kernel for the same layers with another activation: such
// a model is refused, as one of another shape is.
TEST(Newton, AShapeWithFixedActivationsRefusesAModelWithOthers) {
  using C = test::HaselFixedCapacity;
  using S = test::HaselFixedShape;
  RolloutKernels<C> k;
  auto fixed = test::ShapeModel<C, S>::make(2, Activation::Relu, Activation::Relu);
  ASSERT_EQ(finalize_model(fixed.model), Status::Ok);
  EXPECT_EQ(fixed.model.layer[2].act, Activation::Linear);  // the shape's, not the arguments'
  EXPECT_EQ(select_kernels(fixed.model, k), Status::Ok);
  for (int l = 0; l < 3; ++l) {
    auto other = test::random_model<C>(6, 3, 18, 2, {{LayerKind::Dense, 5, l == 0 ? Activation::Relu : Activation::Tanh},
                                                     {LayerKind::Dense, 5, l == 1 ? Activation::Relu : Activation::Tanh},
                                                     {LayerKind::Dense, 3, l == 2 ? Activation::Tanh : Activation::Linear}},
                                       2);
    ASSERT_EQ(finalize_model(other.model), Status::Ok);
    RolloutKernels<C> none;
    EXPECT_EQ(select_kernels(other.model, none), Status::Unsupported) << "layer " << l;
    EXPECT_EQ(none.values, nullptr);
  }
}

TEST(Newton, RecursiveHorizonWarmStartMatchesLongSolve) {
  // N = 4, Nc = 2 with smoothing: the optimum is found by a long solve; a
  // warm start near it reaches it to 1e-4 within three iterations. The
  // reference is a path the model can follow (the loop's situation), so
  // the Gauss-Newton Hessian is the Hessian up to the smoothing's small
  // residual; far from any reachable path it converges linearly.
  const int m = 2, n = 3;
  auto o = test::random_model<Cap>(m, n, 3, 2,
                                   {{LayerKind::Gru, 5, Activation::Tanh}, {LayerKind::Dense, n, Activation::Tanh}}, 9,
                                   0.6f);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  std::vector<float> x0(o.model.p(), 0.1f);
  std::vector<float> ref(4 * n);
  static HorizonScratch<Cap, float> hs;
  const float ustar[4] = {0.3f, -0.2f, 0.1f, 0.25f};
  predict_horizon(o.model, x0.data(), ustar, 4, 2, ref.data(), hs);
  auto P = base_params<Cap>(m, n, 4, 2);
  P.Lambda[0] = P.Lambda[1] = 0.5f;
  P.nr_max_iter = 30;
  P.nr_tol = 1e-7f;
  static SolverScratch<Cap> s;
    SolverState st;
  float Ulong[4] = {0, 0, 0, 0};
  newton_solve(o.model, kernels_of(o.model), P, x0.data(), ref.data(), Ulong, st, s);
  float U[4] = {Ulong[0] + 0.02f, Ulong[1] - 0.02f, Ulong[2] + 0.01f, Ulong[3]};
  P.nr_max_iter = 3;
  P.nr_tol = 1e-4f;
  const NewtonResult res = newton_solve(o.model, kernels_of(o.model), P, x0.data(), ref.data(), U, st, s);
  EXPECT_TRUE(res.flags & kConverged) << "step " << res.step;
  EXPECT_LE(res.iterations, 3);
  for (int a = 0; a < 4; ++a) EXPECT_NEAR(U[a], Ulong[a], 1e-4);
}

TEST(Newton, FlatModelKeepsUFinite) {
  // A model whose output ignores u entirely and no smoothing: H = 0, g = 0.
  auto o = test::random_model<Cap>(1, 1, 0, 2, {{LayerKind::Dense, 1, Activation::Linear}}, 2);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  const uint32_t w0 = o.model.layer[0].offset;
  o.params[w0 + 0] = 0.0f;  // weight of u(k)
  o.params[w0 + 1] = 0.0f;  // weight of u(k-1)
  auto P = base_params<Cap>(1, 1, 1, 1);
  float x0[4] = {0.1f, 0.1f, 0.2f, 0.2f}, ref[1] = {3.0f}, U[1] = {0.4f};
  static SolverScratch<Cap> s;
    SolverState st;
  const NewtonResult res = newton_solve(o.model, kernels_of(o.model), P, x0, ref, U, st, s);
  EXPECT_TRUE(res.flags & kConverged);
  EXPECT_TRUE(std::isfinite(U[0]));
  EXPECT_FLOAT_EQ(U[0], 0.4f);  // zero gradient: nothing to do
}
