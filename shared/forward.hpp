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
  T a[Cap::width];
  T b[Cap::width];
  T gates[Cap::width];
};

// The input normalisation x_net = (x - offset) * scale, folded into the
// first layer so the raw input is never copied (a host Jet is kilobytes).
struct InputAffine {
  const float* scale = nullptr;
  const float* offset = nullptr;
  float s(int i) const { return scale ? scale[i] : 1.0f; }
  float o(int i) const { return scale ? offset[i] * scale[i] : 0.0f; }
};

// The first layer's response to the inputs that stay constant through a
// control step (the sensor signals: every rollout of the horizon and every
// Newton iteration sees the same l(k)), bias included. Computed once per
// step, it spares each forward pass the w x (first layer width) products.
struct ConstantInputs {
  const float* pre = nullptr;  // per first-layer output (3u for a GRU)
  int from = 0;                // inputs [from, p) are folded into pre
};

namespace detail {
// out[j] = bias[j] + x_net W[:, j] for j < cols, W row-major [rows][ld].
// With `c`, rows from c.from on are already in c.pre.
template <class T>
void affine_layer(const float* W, int rows, int ld, int cols, const float* bias, const T* x, T* out,
                  const InputAffine& in, const ConstantInputs& c = {}) {
  if (c.pre) {
    for (int j = 0; j < cols; ++j) set_constant(out[j], c.pre[j]);
    rows = c.from;
  } else {
    for (int j = 0; j < cols; ++j) set_constant(out[j], bias[j]);
  }
  for (int i = 0; i < rows; ++i) {
    const float* row = W + i * ld;
    const float s = in.s(i), o = in.o(i);
    for (int j = 0; j < cols; ++j) mul_add(out[j], x[i], row[j], s, o);
  }
}
}  // namespace detail

// y = act(x W + b), W stored [in][out] (Keras Dense).
template <class T>
void dense(const Layer& L, const float* W, const T* x, T* y, const InputAffine& in = {},
           const ConstantInputs& c = {}) {
  detail::affine_layer(W, L.in, L.out, L.out, W + uint32_t(L.in) * L.out, x, y, in, c);
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
void gru(const Layer& L, const float* W, const T* x, const float* h_prev, T* h, T* gates,
         const InputAffine& in = {}, const ConstantInputs& c = {}) {
  const int u = L.out, g3 = 3 * u;
  const float* rec = W + uint32_t(L.in) * g3;
  const float* bias_in = rec + uint32_t(u) * g3;
  const float* bias_rec = L.reset_after ? bias_in + g3 : nullptr;
  detail::affine_layer(W, L.in, g3, g3, bias_in, x, gates, in, c);

  // recurrent contributions are constants: h_prev does not depend on x
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
      mul_add(hh[j], r[j], rec_term(2 * u + j));
    } else if (h_prev) {
      for (int i = 0; i < u; ++i) mul_add(hh[j], r[i], h_prev[i] * rec[uint32_t(i) * g3 + 2 * u + j]);
    }
    apply(L.act, hh[j]);
  }
  for (int j = 0; j < u; ++j) {
    affine(z[j], -1.0f, 1.0f);       // z <- 1 - z
    multiply(h[j], z[j], hh[j]);     // (1 - z) h~
    if (h_prev) {                    // + z h_prev = + h_prev - (1 - z) h_prev
      mul_add(h[j], z[j], -h_prev[j]);
      affine(h[j], 1.0f, h_prev[j]);
    }
  }
}

// Fills pre (first-layer width floats) with the first layer's bias plus the
// normalised sensor inputs of x times their weights; see ConstantInputs.
template <class Cap>
ConstantInputs constant_inputs(const Model<Cap>& M, const float* x, float* pre) {
  const Layer& L = M.layer[0];
  const int cols = layer_columns(L.kind, L.out);
  const float* W = M.weights(L);
  const float* bias = W + uint32_t(L.in) * cols + (layer_recurrent(uint8_t(L.kind)) ? uint32_t(L.out) * cols : 0u);
  const InputAffine in{M.in_scale(), M.in_offset()};
  const int from = M.nd * M.m + M.dd * M.n;  // the sensor block (Algorithm 1)
  for (int j = 0; j < cols; ++j) pre[j] = bias[j];
  for (int i = from; i < L.in; ++i) {
    const float xi = x[i] * in.s(i) - in.o(i);
    for (int j = 0; j < cols; ++j) pre[j] += xi * W[uint32_t(i) * cols + j];
  }
  return ConstantInputs{pre, from};
}

// y_hat = g(x): normalise, run the layers, de-normalise (see model.hpp).
// `c` (optional) holds the first layer's constant part for this x's sensors.
template <class Cap, class T>
void forward(const Model<Cap>& M, const T* x, T* y, ForwardScratch<Cap, T>& s, const ConstantInputs& c = {}) {
  InputAffine in{M.in_scale(), M.in_offset()};
  ConstantInputs first = c;
  const T* cur = x;
  T* out = s.a;
  for (int l = 0; l < M.layer_count; ++l) {
    const Layer& L = M.layer[l];
    if (L.kind == LayerKind::Dense)
      dense(L, M.weights(L), cur, out, in, first);
    else
      gru(L, M.weights(L), cur, nullptr, out, s.gates, in, first);
    in = InputAffine{};
    first = ConstantInputs{};
    cur = out;
    out = (out == s.a) ? s.b : s.a;
  }
  const float* oo = M.out_offset();
  const float* os = M.out_scale();
  const int y_newest = M.nd * M.m;  // y(k) in the input vector (Algorithm 1)
  for (int j = 0; j < M.n; ++j) {
    y[j] = cur[j];
    affine(y[j], os[j], oo[j]);
    if (M.residual) mul_add(y[j], x[y_newest + j], 1.0f);
  }
}

}  // namespace nlsoft
