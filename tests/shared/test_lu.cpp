// The hand-written LU against Eigen's partial-pivot LU.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "shared/lu.hpp"

using namespace nlsoft;

TEST(Lu, SolvesLikeEigenOnRandomSystems) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> d(-1.0f, 1.0f);
  for (int k : {1, 2, 3, 6, 12}) {
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::MatrixXf A(k, k);
      Eigen::VectorXf b(k);
      for (int i = 0; i < k; ++i) {
        b(i) = d(rng);
        for (int j = 0; j < k; ++j) A(i, j) = d(rng);
      }
      A += Eigen::MatrixXf::Identity(k, k) * 0.1f;  // keep away from singular
      const Eigen::VectorXf ref = A.cast<double>().partialPivLu().solve(b.cast<double>()).cast<float>();
      float LU[144], x[12];
      int piv[12];
      for (int i = 0; i < k; ++i) {
        x[i] = b(i);
        for (int j = 0; j < k; ++j) LU[i * 12 + j] = A(i, j);
      }
      ASSERT_TRUE(lu_decompose(LU, k, 12, piv));
      lu_solve(LU, k, 12, piv, x);
      const float cond = float(A.cast<double>().inverse().norm() * A.cast<double>().norm());
      for (int i = 0; i < k; ++i) EXPECT_NEAR(x[i], ref(i), 1e-6f * cond * (1.0f + std::abs(ref(i)))) << k;
    }
  }
}

TEST(Lu, PivotsOnAZeroDiagonal) {
  float A[4] = {0.0f, 1.0f, 2.0f, 3.0f};  // needs a row exchange
  float b[2] = {1.0f, 8.0f};              // x = [2.5, 1]
  int piv[2];
  ASSERT_TRUE(lu_decompose(A, 2, 2, piv));
  lu_solve(A, 2, 2, piv, b);
  EXPECT_FLOAT_EQ(b[0], 2.5f);
  EXPECT_FLOAT_EQ(b[1], 1.0f);
}

TEST(Lu, ReportsSingularAndNonFiniteMatrices) {
  float S[4] = {1.0f, 2.0f, 2.0f, 4.0f};
  int piv[2];
  EXPECT_FALSE(lu_decompose(S, 2, 2, piv));
  float Z[4] = {0, 0, 0, 0};
  EXPECT_FALSE(lu_decompose(Z, 2, 2, piv));
  float N[4] = {1.0f, std::nanf(""), 0.0f, 1.0f};
  EXPECT_FALSE(lu_decompose(N, 2, 2, piv));
  float I[4] = {1.0f, 0.0f, 0.0f, INFINITY};
  EXPECT_FALSE(lu_decompose(I, 2, 2, piv));
}
