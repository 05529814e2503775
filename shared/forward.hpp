#pragma once
// Network evaluation y_hat(k+1) = g(x(k)) with Keras semantics, written once
// over the scalar type T (float for values and the `fd` stencil, Jet for the
// `exact` derivatives).
#include "shared/jet.hpp"
#include "shared/model.hpp"

namespace nlsoft {

// Caller-owned scratch for one forward pass; nothing is allocated.
template <class Cap, class T>
struct ForwardScratch {
  T xin[Derived<Cap>::p];
  T a[Cap::width];
  T b[Cap::width];
  T gates[Cap::width];
};

// y = act(x W + b), W stored [in][out] (Keras Dense).
template <class T>
void dense(const Layer& L, const float* W, const T* x, T* y) {
  const float* bias = W + uint32_t(L.in) * L.out;
  for (int j = 0; j < L.out; ++j) set_constant(y[j], bias[j]);
  for (int i = 0; i < L.in; ++i) {
    const float* row = W + uint32_t(i) * L.out;
    for (int j = 0; j < L.out; ++j) mul_add(y[j], x[i], row[j]);
  }
  for (int j = 0; j < L.out; ++j) apply(L.act, y[j]);
}

// One GRU step (Keras GRUCell). h_prev is a constant state (nullptr = zero,
// the single-timestep use of the paper); gates holds 3u scratch values.
//   z = rec_act(x Wz + bz + h_prev Uz + rbz)
//   r = rec_act(x Wr + br + h_prev Ur + rbr)
//   reset_after:  h~ = act(x Wh + bh + r * (h_prev Uh + rbh))
//   otherwise:    h~ = act(x Wh + bh + (r * h_prev) Uh)
//   h = z * h_prev + (1 - z) * h~
// The recurrent kernel is read [u][3u], row = previous unit (not transposed).
template <class T>
void gru(const Layer& L, const float* W, const T* x, const float* h_prev, T* h, T* gates) {
  const int u = L.out, g3 = 3 * u;
  const float* kernel = W;
  const float* rec = W + uint32_t(L.in) * g3;
  const float* bias_in = rec + uint32_t(u) * g3;
  const float* bias_rec = L.reset_after ? bias_in + g3 : nullptr;

  // input contributions x W + b for all three gates
  for (int j = 0; j < g3; ++j) set_constant(gates[j], bias_in[j]);
  for (int i = 0; i < L.in; ++i) {
    const float* row = kernel + uint32_t(i) * g3;
    for (int j = 0; j < g3; ++j) mul_add(gates[j], x[i], row[j]);
  }
  // recurrent contributions (constants: h_prev does not depend on x)
  auto rec_term = [&](int col) {
    float s = bias_rec ? bias_rec[col] : 0.0f;
    if (h_prev)
      for (int i = 0; i < u; ++i) s += h_prev[i] * rec[uint32_t(i) * g3 + col];
    return s;
  };
  T* z = gates;
  T* r = gates + u;
  T* hh = gates + 2 * u;
  for (int j = 0; j < u; ++j) {
    affine(z[j], 1.0f, rec_term(j));
    apply(L.rec_act, z[j]);
    affine(r[j], 1.0f, rec_term(u + j));
    apply(L.rec_act, r[j]);
  }
  for (int j = 0; j < u; ++j) {
    if (L.reset_after) {
      T t = r[j];
      affine(t, rec_term(2 * u + j), 0.0f);
      add(hh[j], hh[j], t);
    } else if (h_prev) {
      for (int i = 0; i < u; ++i) mul_add(hh[j], r[i], h_prev[i] * rec[uint32_t(i) * g3 + 2 * u + j]);
    }
    apply(L.act, hh[j]);
  }
  for (int j = 0; j < u; ++j) {
    // h = z*h_prev + (1 - z)*h~
    T one_minus_z = z[j];
    affine(one_minus_z, -1.0f, 1.0f);
    multiply(h[j], one_minus_z, hh[j]);
    if (h_prev) {
      T zh = z[j];
      affine(zh, h_prev[j], 0.0f);
      add(h[j], h[j], zh);
    }
  }
}

// y_hat = g(x): normalise, run the layers, de-normalise (see model.hpp).
template <class Cap, class T>
void forward(const Model<Cap>& M, const T* x, T* y, ForwardScratch<Cap, T>& s) {
  const int p = M.p();
  const float* off = M.in_offset();
  const float* sc = M.in_scale();
  for (int i = 0; i < p; ++i) {
    s.xin[i] = x[i];
    affine(s.xin[i], sc[i], -off[i] * sc[i]);
  }
  const T* in = s.xin;
  T* out = s.a;
  for (int l = 0; l < M.layer_count; ++l) {
    const Layer& L = M.layer[l];
    if (L.kind == LayerKind::Dense)
      dense(L, M.weights(L), in, out);
    else
      gru(L, M.weights(L), in, nullptr, out, s.gates);
    in = out;
    out = (out == s.a) ? s.b : s.a;
  }
  const float* oo = M.out_offset();
  const float* os = M.out_scale();
  const int y_newest = M.nd * M.m;  // y(k) in the input vector (Algorithm 1)
  for (int j = 0; j < M.n; ++j) {
    y[j] = in[j];
    affine(y[j], os[j], oo[j]);
    if (M.residual) add(y[j], y[j], x[y_newest + j]);
  }
}

}  // namespace nlsoft
