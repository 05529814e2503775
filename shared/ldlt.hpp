#pragma once
// A = L D L^T of a symmetric positive-definite k x k matrix (row-major,
// leading dimension ld), in place: L's strict lower triangle below the
// diagonal, D on it; the upper triangle is not read. The Gauss-Newton matrix
// of eq. 5 plus damping is symmetric positive definite, so this needs
// half the work of pivoted LU and no square roots. Hand-written because
// Eigen's fixed-size LDLT costs more flash than the whole solver on an MCU;
// tests hold it against Eigen::LDLT.
#include "shared/hot_path.hpp"

namespace nlsoft {

// False when a pivot is not above 1e-10 of the largest diagonal entry or
// anything is not finite: the matrix is then not (numerically) positive
// definite and A is unusable.
inline bool ldlt_decompose(float* A, int k, int ld) {
  float scale = 0.0f;
  for (int i = 0; i < k; ++i) {
    const float d = A[i * ld + i];
    if (!(d - d == 0.0f)) return false;
    if (d > scale) scale = d;
  }
  if (!(scale > 0.0f)) return false;
  const float tiny = scale * 1e-10f;
  float v[64];  // L[j][p] D[p] of the current row; k <= 64 (the largest capacity's K is 32)
  if (k > 64) return false;
  for (int j = 0; j < k; ++j) {
    float* Aj = A + j * ld;
    float d = Aj[j];
    for (int p = 0; p < j; ++p) {
      v[p] = Aj[p] * A[p * ld + p];
      d -= Aj[p] * v[p];
    }
    if (!(d > tiny) || !(d - d == 0.0f)) return false;
    Aj[j] = d;
    const float inv = 1.0f / d;
    for (int i = j + 1; i < k; ++i) {
      float* Ai = A + i * ld;
      float s = Ai[j];
      for (int p = 0; p < j; ++p) s -= Ai[p] * v[p];
      Ai[j] = s * inv;
    }
  }
  return true;
}

// Solves A x = b with the factors of ldlt_decompose; b is overwritten with x.
inline void ldlt_solve(const float* LD, int k, int ld, float* b) {
  for (int i = 1; i < k; ++i)
    for (int p = 0; p < i; ++p) b[i] -= LD[i * ld + p] * b[p];
  for (int i = 0; i < k; ++i) b[i] /= LD[i * ld + i];
  for (int i = k - 2; i >= 0; --i)
    for (int p = i + 1; p < k; ++p) b[i] -= LD[p * ld + i] * b[p];
}

// The same for a compile-time size K (ld = K), every loop unrolled: the
// MCU's Newton system is 6 x 6, where loop control would cost more than
// the arithmetic.
template <int K>
inline bool ldlt_decompose_fixed(float* A) {
  float scale = 0.0f;
NLSOFT_UNROLL(8)
  for (int i = 0; i < K; ++i) {
    const float d = A[i * K + i];
    if (!(d - d == 0.0f)) return false;
    scale = d > scale ? d : scale;
  }
  if (!(scale > 0.0f)) return false;
  const float tiny = scale * 1e-10f;
NLSOFT_UNROLL(8)
  for (int j = 0; j < K; ++j) {
    float v[K];
    float d = A[j * K + j];
NLSOFT_UNROLL(8)
    for (int p = 0; p < j; ++p) {
      v[p] = A[j * K + p] * A[p * K + p];
      d -= A[j * K + p] * v[p];
    }
    if (!(d > tiny) || !(d - d == 0.0f)) return false;
    A[j * K + j] = d;
    const float inv = 1.0f / d;
NLSOFT_UNROLL(8)
    for (int i = j + 1; i < K; ++i) {
      float s = A[i * K + j];
NLSOFT_UNROLL(8)
      for (int p = 0; p < j; ++p) s -= A[i * K + p] * v[p];
      A[i * K + j] = s * inv;
    }
  }
  return true;
}

template <int K>
inline void ldlt_solve_fixed(const float* LD, float* b) {
NLSOFT_UNROLL(8)
  for (int i = 1; i < K; ++i)
NLSOFT_UNROLL(8)
    for (int p = 0; p < i; ++p) b[i] -= LD[i * K + p] * b[p];
NLSOFT_UNROLL(8)
  for (int i = 0; i < K; ++i) b[i] /= LD[i * K + i];
NLSOFT_UNROLL(8)
  for (int i = K - 2; i >= 0; --i)
NLSOFT_UNROLL(8)
    for (int p = i + 1; p < K; ++p) b[i] -= LD[p * K + i] * b[p];
}

}  // namespace nlsoft
