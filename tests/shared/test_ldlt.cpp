// LDL^T against Eigen on random symmetric positive-definite systems.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "shared/ldlt.hpp"

using namespace nlsoft;

TEST(Ldlt, SolvesLikeEigenOnRandomSpdSystems) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (int k = 1; k <= 12; ++k) {
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::MatrixXd B(k, k);
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) B(i, j) = d(rng);
      const Eigen::MatrixXd A = B * B.transpose() + 0.5 * Eigen::MatrixXd::Identity(k, k);
      Eigen::VectorXd b(k);
      for (int i = 0; i < k; ++i) b(i) = d(rng);
      const Eigen::VectorXd want = A.ldlt().solve(b);
      float LD[12 * 12], x[12];
      for (int i = 0; i < k; ++i) {
        for (int j = 0; j < k; ++j) LD[i * 12 + j] = j <= i ? float(A(i, j)) : NAN;  // upper triangle unread
        x[i] = float(b(i));
      }
      ASSERT_TRUE(ldlt_decompose(LD, k, 12));
      ldlt_solve(LD, k, 12, x);
      for (int i = 0; i < k; ++i) EXPECT_NEAR(x[i], want(i), 1e-3 * (1.0 + std::fabs(want(i)))) << "k " << k;
    }
  }
}

TEST(Ldlt, RefusesIndefiniteSingularAndNonFiniteMatrices) {
  float indefinite[4] = {1, 0, 2, 1};  // [[1,2],[2,1]]: eigenvalues 3, -1
  EXPECT_FALSE(ldlt_decompose(indefinite, 2, 2));
  float singular[4] = {1, 0, 1, 1};    // [[1,1],[1,1]]
  EXPECT_FALSE(ldlt_decompose(singular, 2, 2));
  float zero[4] = {0, 0, 0, 0};
  EXPECT_FALSE(ldlt_decompose(zero, 2, 2));
  float nan[4] = {1, 0, NAN, 1};
  EXPECT_FALSE(ldlt_decompose(nan, 2, 2));
  float inf[4] = {INFINITY, 0, 0, 1};
  EXPECT_FALSE(ldlt_decompose(inf, 2, 2));
}
