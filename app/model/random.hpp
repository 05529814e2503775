#pragma once
// Seeded random numbers that give the same stream on every platform and
// standard library: std::mt19937_64 is fully specified, the distributions
// of <random> are not, so the few we need are written here.
#include <cmath>
#include <cstdint>
#include <random>

#include "shared/fixed_math.hpp"

namespace nlsoft::model {

class Random {
 public:
  explicit Random(uint64_t seed) : eng_(seed) {}
  double uniform() { return static_cast<double>(eng_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  long integer(long lo, long hi) {  // [lo, hi]
    return lo + static_cast<long>(uniform() * static_cast<double>(hi - lo + 1));
  }
  double gaussian() {  // Box-Muller, one value per call for simplicity
    const double a = 1.0 - uniform();
    const double b = uniform();
    return std::sqrt(-2.0 * fixed_math::log(a)) * fixed_math::cos(6.283185307179586 * b);
  }
  uint64_t next() { return eng_(); }

 private:
  std::mt19937_64 eng_;
};

}  // namespace nlsoft::model
