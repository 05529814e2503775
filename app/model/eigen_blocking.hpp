#pragma once
// Eigen splits a large matrix product (a gradient X^T delta over thousands
// of rows, a least-squares normal matrix) into blocks sized from the CPU's
// cache sizes, which it reads with CPUID at run time; the blocking sets the
// order of the sums, so the same binary gave other bits on another CPU.
// pin_eigen_blocking() fixes the sizes Eigen plans with. The values are
// the ones Eigen read on the machine the shipped figures were made on (L1
// 48 KiB, L2 2 MiB, L3 480 MiB), so pinning moved no figure there.
// network.cpp calls it from a static initialiser: every program that
// trains or evaluates a network links that file, and the pin is in place
// before main() runs any product.
#include <Eigen/Core>

namespace nlsoft::model {

inline constexpr std::ptrdiff_t kEigenL1Bytes = 48 * 1024;
inline constexpr std::ptrdiff_t kEigenL2Bytes = 2 * 1024 * 1024;
inline constexpr std::ptrdiff_t kEigenL3Bytes = 480 * 1024 * 1024;

inline bool pin_eigen_blocking() {
  Eigen::setCpuCacheSizes(kEigenL1Bytes, kEigenL2Bytes, kEigenL3Bytes);
  return true;
}

}  // namespace nlsoft::model
