#pragma once
// Recursive prediction over the horizon (paper, "Problem Statement"):
// Y_hat in R^{N x n}, each prediction fed back into the y-queue of the next
// input vector; U in R^{Nc x m}, rows past Nc repeat the last one.
//
// x0 is the input vector before the decision at step k: its u-queue holds
// u(k-1)..., its y-queue y(k)..., its sensors l(k). Row j of Y is y_hat(k+1+j).
#include "shared/forward.hpp"
#include "shared/input_vector.hpp"

namespace nlsoft {

template <class Cap, class T>
struct HorizonScratch {
  T x[Dims<Cap>::p];
  ForwardScratch<Cap, T> fw;
};

template <class Cap>
InputLayout layout_of(const Model<Cap>& M) {
  return InputLayout{M.m, M.n, M.w, M.nd, M.dd};
}

// `c`: the first layer's response to x0's sensors (constant_inputs), or none.
template <class Cap, class T>
void predict_horizon(const Model<Cap>& M, const float* x0, const T* U, int N, int Nc, T* Y,
                     HorizonScratch<Cap, T>& s, const ConstantInputs& c = {}) {
  const InputLayout L = layout_of(M);
  for (int i = 0; i < L.p(); ++i) set_constant(s.x[i], x0[i]);
  for (int j = 0; j < N; ++j) {
    push_input(s.x, L, U + (j < Nc ? j : Nc - 1) * L.m);
    if (j > 0) push_output(s.x, L, Y + (j - 1) * L.n);
    forward(M, s.x, Y + j * L.n, s.fw, c);
  }
}

}  // namespace nlsoft
