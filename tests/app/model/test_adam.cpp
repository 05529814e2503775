// app/model/adam.hpp: the one Adam step of train's warm start and its
// simulation epochs.
#include "app/model/adam.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using nlsoft::model::Adam;

// The first step moves each weight by lr against its gradient's sign: the
// bias correction makes m1^ = g and m2^ = g^2 after one step.
TEST(Adam, TheFirstStepIsTheRateAgainstTheGradientsSign) {
  Adam adam(3);
  std::vector<double> th = {1.0, -2.0, 0.5};
  adam.step(th, {0.25, -4.0, 0.0}, 0.1);
  EXPECT_NEAR(th[0], 1.0 - 0.1, 1e-6);
  EXPECT_NEAR(th[1], -2.0 + 0.1, 1e-6);
  EXPECT_EQ(th[2], 0.5);  // no gradient, no step
}

// A scale of 1 is every bit the unscaled step; another scales the gradient
// before the moments see it.
TEST(Adam, AScaleScalesTheGradientBeforeTheMoments) {
  Adam plain(2), unit(2), halved(2), scaled(2);
  std::vector<double> a = {0.3, -0.7}, b = a, c = a, d = a;
  const std::vector<double> g1 = {0.8, 0.1}, g2 = {-0.2, 0.6};
  for (const auto* g : {&g1, &g2}) {
    plain.step(a, *g, 0.01);
    unit.step(b, *g, 0.01, 1.0);
    halved.step(c, {0.5 * (*g)[0], 0.5 * (*g)[1]}, 0.01);
    scaled.step(d, *g, 0.01, 0.5);
  }
  EXPECT_EQ(a, b);
  EXPECT_EQ(c, d);
  EXPECT_EQ(plain.b1t, 0.9 * 0.9);
  EXPECT_EQ(plain.b2t, 0.999 * 0.999);
}
