#pragma once
// Adam (Kingma and Ba), the step both of train's gradient phases take: the
// one-step warm start (train.cpp) and the simulation epochs
// (train_simulation.cpp). Its constants and bias correction are said once,
// so the two cannot drift apart.
#include <cmath>
#include <cstddef>
#include <vector>

namespace nlsoft::model {

struct Adam {
  static constexpr double b1 = 0.9, b2 = 0.999, eps = 1e-8;
  std::vector<double> m1, m2;  // the moment estimates, one per weight
  double b1t = 1.0, b2t = 1.0;  // b1^t, b2^t: the bias correction after t steps

  explicit Adam(size_t weights) : m1(weights, 0.0), m2(weights, 0.0) {}

  // One step of the weights th at rate lr down grad, scaled by `scale` (a
  // clipped gradient's 1 / norm; 1 leaves every bit of it as it is).
  void step(std::vector<double>& th, const std::vector<double>& grad, double lr, double scale = 1.0) {
    b1t *= b1;
    b2t *= b2;
    const double step = lr * std::sqrt(1.0 - b2t) / (1.0 - b1t);
    for (size_t k = 0; k < th.size(); ++k) {
      const double g = scale * grad[k];
      m1[k] = b1 * m1[k] + (1.0 - b1) * g;
      m2[k] = b2 * m2[k] + (1.0 - b2) * g * g;
      th[k] -= step * m1[k] / (std::sqrt(m2[k]) + eps);
    }
  }
};

}  // namespace nlsoft::model
