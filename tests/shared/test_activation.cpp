// The controller's fast activations against libm, with the error bounds that
// activation.hpp states.
#include <gtest/gtest.h>

#include <cmath>

#include "shared/activation.hpp"

using namespace nlsoft;

TEST(FastActivation, ExpRelativeErrorBelowStatedBound) {
  double worst = 0;
  for (double x = -87.0; x <= 88.0; x += 1.0 / 512) {
    const double want = std::exp(x);
    worst = std::max(worst, std::fabs(fast_exp(float(x)) - want) / want);
  }
  EXPECT_LT(worst, 2.5e-7);
  EXPECT_EQ(fast_exp(-1000.0f), fast_exp(-87.0f));  // clamped, never zero or denormal
  EXPECT_TRUE(std::isfinite(fast_exp(1000.0f)));
  EXPECT_TRUE(std::isfinite(fast_exp(NAN)));
}

TEST(FastActivation, TanhAndSigmoidAbsoluteErrorBelowStatedBound) {
  double tanh_worst = 0, sig_worst = 0;
  for (double x = -20.0; x <= 20.0; x += 1.0 / 1024) {
    const float xf = float(x);
    tanh_worst = std::max(tanh_worst, std::fabs(fast_tanh(xf) - std::tanh(double(xf))));
    sig_worst = std::max(sig_worst, std::fabs(fast_sigmoid(xf) - 1.0 / (1.0 + std::exp(-double(xf)))));
  }
  EXPECT_LT(tanh_worst, 3e-7);
  EXPECT_LT(sig_worst, 3e-7);
  EXPECT_EQ(fast_tanh(0.0f), 0.0f);
  EXPECT_EQ(fast_tanh(50.0f), 1.0f);
  EXPECT_EQ(fast_tanh(-50.0f), -1.0f);
}

TEST(FastActivation, SlopesAreTheDerivatives) {
  for (Activation a : {Activation::Linear, Activation::Relu, Activation::Tanh, Activation::Sigmoid,
                       Activation::HardSigmoid}) {
    for (float x : {-3.1f, -0.7f, 0.3f, 1.9f}) {
      const ActSlope s = activate_slope(a, x);
      const ActValue r = activate_d2(a, x);
      EXPECT_NEAR(s.f, r.f, 3e-7) << int(a) << " at " << x;
      EXPECT_NEAR(s.df, r.df, 1e-6) << int(a) << " at " << x;
    }
  }
}
