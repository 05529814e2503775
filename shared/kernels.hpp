#pragma once
// The controller's rollout specialised for a network shape known at compile
// time (net_shape.hpp): the same arithmetic as the generic rollout
// (rollout.hpp), and tests hold the two to each other, but every layer size
// is a constant, so the inner loops unroll and the accumulators of a unit's
// value and tangent stay in registers. Only the inner loops are unrolled
// (over a layer's outputs and the K tangent columns); the loops over inputs
// and horizon steps stay loops, which keeps a kernel near 1-2 kB of flash.
//
// select_kernels() picks, for a model, the specialised kernel of its shape,
// or the generic one where the capacity keeps it.
#include "shared/rollout.hpp"

// See rollout.hpp: the step's hot code is compiled for speed even in images
// built for size.
#pragma GCC push_options
#pragma GCC optimize("O2")

namespace nlsoft {

// One rollout: Y (N x n) and, for the Jacobian kernel, G (N n rows of K).
template <class Cap>
using RolloutFn = void (*)(const Model<Cap>&, const float* x0, const float* U, int N, int Nc, const ConstantInputs&,
                           float* Y, float* G, RolloutScratch<Cap>&);

template <class Cap>
using ConstantFn = ConstantInputs (*)(const Model<Cap>&, const float* x0, float* pre);

template <class Cap>
struct RolloutKernels {
  ConstantFn<Cap> constant = nullptr;  // the first layer's part that U does not touch, once per step
  RolloutFn<Cap> values = nullptr;     // Y only (fd stencil, the step check)
  RolloutFn<Cap> jacobian = nullptr;   // Y and G (exact)
};

namespace detail {

// A Dense layer past the first, In inputs to Out units.
template <int K, bool kTangents, int In, int Out>
inline void dense_fixed(Activation act, const float* W, const float* x, const float (*Tx)[K], uint8_t* live,
                        float* y, float (*Ty)[K]) {
  const float* bias = W + In * Out;
  float z[Out];
#pragma GCC unroll 16
  for (int j = 0; j < Out; ++j) z[j] = bias[j];
  for (int i = 0; i < In; ++i) {
    const float xi = x[i];
    const float* w = W + i * Out;
#pragma GCC unroll 16
    for (int j = 0; j < Out; ++j) z[j] += xi * w[j];
  }
  float df[Out];
  activate_slopes(act, z, df, Out);
#pragma GCC unroll 16
  for (int j = 0; j < Out; ++j) y[j] = z[j];
  if constexpr (kTangents) {
    uint8_t on[In];  // the inputs whose tangent is not zero
    int count = 0;
    for (int i = 0; i < In; ++i)
      if (live[i]) on[count++] = uint8_t(i);
    for (int j = 0; j < Out; ++j) {
      float acc[K];
      tangent_zero<K>(acc);
      if (df[j] != 0.0f)
        for (int c = 0; c < count; ++c) tangent_axpy<K>(acc, W[on[c] * Out + j], Tx[on[c]]);
      tangent_scale<K>(Ty[j], acc, df[j]);
    }
#pragma GCC unroll 16
    for (int j = 0; j < Out; ++j) live[j] = df[j] != 0.0f;
  }
}

}  // namespace detail

// The rollout of rollout.hpp for models of shape S.
template <class Cap, class S, bool kTangents>
struct ShapedRollout;

template <class Cap, int M, int N, int W, int ND, class First, class... Rest, bool kTangents>
struct ShapedRollout<Cap, NetShape<M, N, W, ND, First, Rest...>, kTangents> {
  using S = NetShape<M, N, W, ND, First, Rest...>;
  static constexpr int K = Dims<Cap>::K;
  static constexpr int kQ = S::queue, kC0 = First::cols;
  static_assert(S::m <= Cap::m && S::n <= Cap::n && S::w <= Cap::w && S::nd <= Cap::nd, "shape exceeds capacity");
  static_assert(kC0 <= Cap::width, "first layer exceeds capacity");

  // Whether model M has this shape (activations are run-time data).
  static bool matches(const Model<Cap>& Mo) {
    if (Mo.m != M || Mo.n != N || Mo.w != W || Mo.nd != ND || Mo.dd != ND || Mo.layer_count != S::layers)
      return false;
    const bool kinds[] = {First::gru, Rest::gru...};
    const int units[] = {First::units, Rest::units...};
    for (int l = 0; l < S::layers; ++l)
      if ((Mo.layer[l].kind == LayerKind::Gru) != kinds[l] || Mo.layer[l].out != units[l]) return false;
    return true;
  }

  template <int In, class L, class... More>
  static int layers(const Model<Cap>& Mo, int l, RolloutScratch<Cap>& s, int cur) {
    static_assert(!L::gru, "a GRU runs only as the first layer of a shaped kernel");
    static_assert(L::units <= Cap::width, "layer exceeds capacity");
    const Layer& Lr = Mo.layer[l];
    detail::dense_fixed<K, kTangents, In, L::units>(Lr.act, Mo.weights(Lr), s.v[cur], s.T[cur], s.live,
                                                     s.v[1 - cur], s.T[1 - cur]);
    cur = 1 - cur;
    if constexpr (sizeof...(More) > 0)
      return layers<L::units, More...>(Mo, l + 1, s, cur);
    else
      return cur;
  }

  // What U does not touch in the first layer, once per control step: its
  // bias plus the sensor signals' products (forward.hpp's constant_inputs()),
  // and for the first ND horizon steps the products of the history entries
  // that still come from x0. Row j (j < ND) serves step j, row ND every
  // later step: (ND + 1) x kC0 floats.
  static ConstantInputs constant(const Model<Cap>& Mo, const float* x0, float* pre) {
    const float* W0 = Mo.weights(Mo.layer[0]);
    const float* bias = W0 + S::p * kC0 + (First::gru ? First::units * kC0 : 0);
    const float* sc = Mo.in_scale();
    const float* off = Mo.in_offset();
    float z[kC0];
#pragma GCC unroll 32
    for (int q = 0; q < kC0; ++q) z[q] = bias[q];
    for (int i = S::queue; i < S::p; ++i) add_entry(z, W0, (x0[i] - off[i]) * sc[i], i);
    for (int q = 0; q < kC0; ++q) pre[ND * kC0 + q] = z[q];
    for (int j = 0; j < ND; ++j) {
      float r[kC0];
#pragma GCC unroll 32
      for (int q = 0; q < kC0; ++q) r[q] = z[q];
      for (int t = j + 1; t < ND; ++t)  // u-slot t holds u(k+j-t), from x0
        for (int i = 0; i < M; ++i) {
          const int e = t * M + i, xi = (t - j - 1) * M + i;
          add_entry(r, W0, (x0[xi] - off[e]) * sc[e], e);
        }
      for (int t = j; t < ND; ++t)  // y-slot t holds y(k+j-t), from x0
        for (int i = 0; i < N; ++i) {
          const int e = ND * M + t * N + i, xi = ND * M + (t - j) * N + i;
          add_entry(r, W0, (x0[xi] - off[e]) * sc[e], e);
        }
      for (int q = 0; q < kC0; ++q) pre[j * kC0 + q] = r[q];
    }
    return ConstantInputs{pre, S::queue};
  }

  // z += x W1[e]
  static inline void add_entry(float* z, const float* W0, float x, int e) {
    const float* w = W0 + e * kC0;
#pragma GCC unroll 32
    for (int q = 0; q < kC0; ++q) z[q] += x * w[q];
  }

  static void run(const Model<Cap>& Mo, const float* x0, const float* U, int Nh, int Nc, const ConstantInputs& c,
                  float* Y, float* G, RolloutScratch<Cap>& s) {
    const float* sc = Mo.in_scale();
    const float* off = Mo.in_offset();
    const float* W0 = Mo.weights(Mo.layer[0]);
    const float* os = Mo.out_scale();
    const float* oo = Mo.out_offset();
    constexpr int kU = ND * M;  // first y-queue entry

    for (int j = 0; j < Nh; ++j) {
      // ---- first layer: z = pre_j + the entries of x(k+j) that hold U or
      // a prediction (Algorithm 1; the rest is in pre_j, see constant()) ----
      const int preds = j < ND ? j : ND;          // y-slots holding predictions
      const int slots = j + 1 < ND ? j + 1 : ND;  // u-slots holding U
      float* z = s.v[0];
      float zr[kC0];
      const float* prow = c.pre + (j < ND ? j : ND) * kC0;
#pragma GCC unroll 32
      for (int q = 0; q < kC0; ++q) zr[q] = prow[q];
      for (int t = 0; t < slots; ++t) {  // u-slot t holds U's row j - t
        const float* u = U + (j - t < Nc ? j - t : Nc - 1) * M;
        for (int i = 0; i < M; ++i) add_entry(zr, W0, (u[i] - off[t * M + i]) * sc[t * M + i], t * M + i);
      }
      for (int t = 0; t < preds; ++t) {  // y-slot t holds y_hat(k+j-t)
        const float* y = Y + (j - t - 1) * N;
        const int e0 = kU + t * N;
        for (int i = 0; i < N; ++i) add_entry(zr, W0, (y[i] - off[e0 + i]) * sc[e0 + i], e0 + i);
      }
#pragma GCC unroll 32
      for (int q = 0; q < kC0; ++q) z[q] = zr[q];

      if constexpr (kTangents) {
        for (int q = 0; q < kC0; ++q) {
          float acc[K];
          detail::tangent_zero<K>(acc);
          // a prediction enters with its row of G: dz += sc_e W1[e][q] dy
          for (int t = 0; t < preds; ++t) {
            const int e0 = kU + t * N;
            const float* g = G + (j - t - 1) * N * K;
#pragma GCC unroll 8
            for (int i = 0; i < N; ++i)
              detail::tangent_axpy<K>(acc, sc[e0 + i] * W0[(e0 + i) * kC0 + q], g + i * K);
          }
          // U itself enters through its weight, into the columns of its row
          // of U; the row is picked among the capacity's Nc blocks so every
          // index is a constant and acc stays in registers.
          for (int t = 0; t < slots; ++t) {
            const int row = j - t < Nc ? j - t : Nc - 1;
#pragma GCC unroll 8
            for (int rr = 0; rr < Cap::Nc; ++rr) {
              if (rr != row) continue;
#pragma GCC unroll 8
              for (int i = 0; i < M; ++i)
                if (rr * M + i < K) acc[rr * M + i] += sc[t * M + i] * W0[(t * M + i) * kC0 + q];
            }
          }
          detail::tangent_scale<K>(s.T[0][q], acc, 1.0f);
        }
      }

      // ---- the first layer's cell, then the rest ----
      int cur = 0;
      const Layer& L0 = Mo.layer[0];
      if constexpr (First::gru) {
        const float* bias_rec = L0.reset_after ? W0 + (S::p + First::units) * kC0 + kC0 : nullptr;
        detail::gru_cell<K, kTangents>(L0, bias_rec, s.v[0], s.T[0], s.v[1], s.T[1], s.live);
        cur = 1;
      } else {
        float df[kC0];
        activate_slopes(L0.act, z, df, kC0);
        if constexpr (kTangents)
          for (int q = 0; q < kC0; ++q) {
            detail::tangent_scale<K>(s.T[0][q], s.T[0][q], df[q]);
            s.live[q] = df[q] != 0.0f;
          }
      }
      if constexpr (sizeof...(Rest) > 0) cur = layers<First::units, Rest...>(Mo, 1, s, cur);

      // ---- output: y = y_net out_scale + out_offset (+ y(k+j) if residual) ----
      for (int i = 0; i < N; ++i) {
        const int r = j * N + i;
        const float prev = j > 0 ? Y[r - N] : x0[kU + i];
        Y[r] = s.v[cur][i] * os[i] + oo[i] + (Mo.residual ? prev : 0.0f);
        if constexpr (kTangents) {
          float* g = G + r * K;
          detail::tangent_scale<K>(g, s.T[cur][i], os[i]);
          if (Mo.residual && j > 0) detail::tangent_axpy<K>(g, 1.0f, g - N * K);
        }
      }
    }
  }
};

namespace detail {

template <class Cap, class S>
bool try_shape(const Model<Cap>& M, RolloutKernels<Cap>& k) {
  if (k.values || !ShapedRollout<Cap, S, false>::matches(M)) return false;
  k.constant = &ShapedRollout<Cap, S, false>::constant;
  k.values = &ShapedRollout<Cap, S, false>::run;
  k.jacobian = &ShapedRollout<Cap, S, true>::run;
  return true;
}

template <class Cap, class... Shapes>
void try_shapes(const Model<Cap>& M, RolloutKernels<Cap>& k, ShapeList<Shapes...>) {
  (try_shape<Cap, Shapes>(M, k), ...);
}

}  // namespace detail

// The kernels for model M: its shape's, else the generic ones if the
// capacity keeps them, else Unsupported (nothing written).
template <class Cap>
Status select_kernels(const Model<Cap>& M, RolloutKernels<Cap>& out) {
  RolloutKernels<Cap> k;
  detail::try_shapes(M, k, typename Cap::Shapes{});
  if (!k.values) {
    if constexpr (Cap::generic) {
      k.constant = &constant_inputs<Cap>;
      k.values = &rollout<Cap, false>;
      k.jacobian = &rollout<Cap, true>;
    } else {
      return Status::Unsupported;
    }
  }
  out = k;
  return Status::Ok;
}

}  // namespace nlsoft

#pragma GCC pop_options
