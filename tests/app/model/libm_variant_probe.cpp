// Prints a hash of glibc's own exp, log, sin, cos, tanh and pow over a few
// thousand arguments: train_cpu_independent.sh runs it with and without
// GLIBC_TUNABLES masking AVX2/FMA to see whether the masking changes which
// code glibc runs on this CPU (the one place that calls libm on purpose).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

int main() {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](double v) {
    uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    h = (h ^ b) * 1099511628211ull;
  };
  for (int i = 0; i < 20000; ++i) {
    volatile double x = -20.0 + 0.002 * i + 1e-9;  // volatile: no constant folding
    mix(std::exp(x));
    mix(std::log(std::fabs(x) + 1e-3));
    mix(std::sin(7.3 * x));
    mix(std::cos(7.3 * x));
    mix(std::tanh(x));
    mix(std::pow(std::fabs(x) + 0.5, 1.37));
  }
  std::printf("%016llx\n", static_cast<unsigned long long>(h));
  return 0;
}
