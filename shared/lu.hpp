#pragma once
// LU decomposition with partial pivoting (Doolittle, row exchanges), in place
// on a row-major k x k matrix with leading dimension ld. Hand-written because
// Eigen's fixed-size LU pulls in more code than the whole controller on an
// MCU; tests hold it against Eigen::PartialPivLU.
#include <cmath>

namespace nlsoft {

// Returns false for a singular or non-finite matrix (a pivot below 1e-12 of
// the largest entry); A is then unusable. The threshold is far below float
// precision on purpose: the cost's Hessian is routinely conditioned 1e8
// (Q = 1e6 against Lambda = 1 on redundant actuators) and still gives the
// right step where it matters; the line search catches the rest.
inline bool lu_decompose(float* A, int k, int ld, int* piv) {
  float scale = 0.0f;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      const float v = std::fabs(A[i * ld + j]);
      if (!(v - v == 0.0f)) return false;
      if (v > scale) scale = v;
    }
  if (scale == 0.0f) return false;
  const float tiny = scale * 1e-12f;
  for (int c = 0; c < k; ++c) {
    int p = c;
    float best = std::fabs(A[c * ld + c]);
    for (int r = c + 1; r < k; ++r) {
      const float v = std::fabs(A[r * ld + c]);
      if (v > best) best = v, p = r;
    }
    if (!(best > tiny)) return false;
    piv[c] = p;
    if (p != c)
      for (int j = 0; j < k; ++j) {
        const float t = A[c * ld + j];
        A[c * ld + j] = A[p * ld + j];
        A[p * ld + j] = t;
      }
    const float inv = 1.0f / A[c * ld + c];
    for (int r = c + 1; r < k; ++r) {
      const float f = A[r * ld + c] * inv;
      A[r * ld + c] = f;
      for (int j = c + 1; j < k; ++j) A[r * ld + j] -= f * A[c * ld + j];
    }
  }
  return true;
}

// Solves A x = b with the factors of lu_decompose; b is overwritten with x.
inline void lu_solve(const float* LU, int k, int ld, const int* piv, float* b) {
  for (int c = 0; c < k; ++c)
    if (piv[c] != c) {
      const float t = b[c];
      b[c] = b[piv[c]];
      b[piv[c]] = t;
    }
  for (int r = 1; r < k; ++r)
    for (int j = 0; j < r; ++j) b[r] -= LU[r * ld + j] * b[j];
  for (int r = k - 1; r >= 0; --r) {
    for (int j = r + 1; j < k; ++j) b[r] -= LU[r * ld + j] * b[j];
    b[r] /= LU[r * ld + r];
  }
}

}  // namespace nlsoft
