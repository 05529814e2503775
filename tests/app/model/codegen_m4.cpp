// Compiled with arm-none-eabi-g++ by CMake: a generated model header builds
// for Cortex-M4F, without heap or exceptions, and runs through forward().
#include "gen_hasel.hpp"
#include "gen_tendon.hpp"
#include "shared/forward.hpp"

float run_hasel(const float* x, float* y) {
  static nlsoft::Model<nlsoft::HaselCapacity> m;
  if (gen_hasel::build(m) != nlsoft::Status::Ok) return -1.0f;
  static nlsoft::ForwardScratch<nlsoft::HaselCapacity, float> s;
  nlsoft::forward(m, x, y, s);
  return y[0];
}

float run_tendon(const float* x, float* y) {
  static nlsoft::Model<nlsoft::TendonCapacity> m;
  if (gen_tendon::build(m) != nlsoft::Status::Ok) return -1.0f;
  static nlsoft::ForwardScratch<nlsoft::TendonCapacity, float> s;
  nlsoft::forward(m, x, y, s);
  return y[0];
}
