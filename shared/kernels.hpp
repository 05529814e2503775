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
#include <utility>

#include "shared/hot_path.hpp"
#include "shared/rollout.hpp"

// See rollout.hpp: the step's hot code is compiled for speed even in images
// built for size.
NLSOFT_HOT_BEGIN

namespace nlsoft {

// One rollout: Y (N x n) and, for the Jacobian kernel, G (N n rows of K).
template <class Cap>
using RolloutFn = void (*)(const Model<Cap>&, const float* x0, const float* U, int N, int Nc, const ConstantInputs&,
                           float* Y, float* G, RolloutScratch<Cap>&);

template <class Cap>
using ConstantFn = ConstantInputs (*)(const Model<Cap>&, const float* x0, float* pre);

// Y at U + delta e_a, from what the last `values` rollout (at U, with the
// same x0 and scratch) left in the scratch: the fd stencil's rollouts.
template <class Cap>
using StencilFn = void (*)(const Model<Cap>&, const float* x0, int N, const ConstantInputs&, int a, float delta,
                           float* Y, RolloutScratch<Cap>&);

template <class Cap>
struct RolloutKernels {
  ConstantFn<Cap> constant = nullptr;  // the first layer's part that U does not touch, once per step
  RolloutFn<Cap> values = nullptr;     // Y only (fd stencil, the step check)
  RolloutFn<Cap> jacobian = nullptr;   // Y and G (exact)
  StencilFn<Cap> stencil = nullptr;    // optional: Y with one input moved, after `values`
};

namespace detail {

// activate_slopes() for a layer of a constant width: ReLU, tanh and linear,
// the shipped models' hidden and output layers, inline and unrolled; the
// others through the call. Known: the layer's activation when the shape
// fixes it (net_shape.hpp), and then only its branch is compiled.
template <int Count, int Known = kActivationAtRunTime>
__attribute__((always_inline)) inline void activate_fixed(Activation run_time, float* z, float* df) {
  const Activation act = Known == kActivationAtRunTime ? run_time : Activation(uint8_t(Known));
  if (act == Activation::Relu) {
NLSOFT_UNROLL(16)
    for (int j = 0; j < Count; ++j) {
      const bool on = z[j] > 0.0f;
      df[j] = on ? 1.0f : 0.0f;
      z[j] = on ? z[j] : 0.0f;
    }
  } else if (act == Activation::Tanh) {
NLSOFT_UNROLL(16)
    for (int j = 0; j < Count; ++j) {
      const float t = fast_tanh(z[j]);
      df[j] = 1.0f - t * t;
      z[j] = t;
    }
  } else if (act == Activation::Linear) {
NLSOFT_UNROLL(16)
    for (int j = 0; j < Count; ++j) df[j] = 1.0f;
  } else {
    activate_slopes(act, z, df, Count);
  }
}

// A Dense layer past the first, In inputs to Out units: y = act(x W + b)
// and the slopes act'(.), which the Jacobian's reverse sweep needs.
template <int In, int Out, int Known>
inline void dense_values(Activation act, const float* W, const float* x, float* y, float* df) {
  const float* bias = W + In * Out;
  float z[Out];
NLSOFT_UNROLL(16)
  for (int j = 0; j < Out; ++j) z[j] = bias[j];
NLSOFT_UNROLL(16)
  for (int i = 0; i < In; ++i) {
    const float xi = x[i];
    const float* w = W + i * Out;
NLSOFT_UNROLL(16)
    for (int j = 0; j < Out; ++j) z[j] += xi * w[j];
  }
  activate_fixed<Out, Known>(act, z, df);
NLSOFT_UNROLL(16)
  for (int j = 0; j < Out; ++j) y[j] = z[j];
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
  static_assert(First::kind == LayerKind::Dense || First::kind == LayerKind::Gru,
                "a shaped kernel's first layer is Dense or GRU: another kind runs on the generic kernel");

  // Whether model M has this shape (and the activations it fixes, if any).
  static bool matches(const Model<Cap>& Mo) {
    if (Mo.m != M || Mo.n != N || Mo.w != W || Mo.nd != ND || Mo.dd != ND || Mo.layer_count != S::layers)
      return false;
    const LayerKind kinds[] = {First::kind, Rest::kind...};
    const int units[] = {First::units, Rest::units...};
    const int acts[] = {First::act, Rest::act...};
    for (int l = 0; l < S::layers; ++l) {
      if (Mo.layer[l].kind != kinds[l] || Mo.layer[l].out != units[l]) return false;
      if (acts[l] != kActivationAtRunTime && int(Mo.layer[l].act) != acts[l]) return false;
    }
    return true;
  }

  // The layers past the first: values, and each layer's slopes in slope[l].
  template <int In, class L, class... More>
  static int layers(const Model<Cap>& Mo, int l, RolloutScratch<Cap>& s, int cur, float (*slope)[Cap::width]) {
    static_assert(L::kind == LayerKind::Dense, "past the first layer a shaped kernel runs Dense layers only");
    static_assert(L::units <= Cap::width, "layer exceeds capacity");
    const Layer& Lr = Mo.layer[l];
    detail::dense_values<In, L::units, L::act>(Lr.act, Mo.weights(Lr), s.v[cur], s.v[1 - cur], slope[l]);
    cur = 1 - cur;
    if constexpr (sizeof...(More) > 0)
      return layers<L::units, More...>(Mo, l + 1, s, cur, slope);
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
NLSOFT_UNROLL(32)
    for (int q = 0; q < kC0; ++q) z[q] = bias[q];
    // every loop here has a constant trip count: unrolled, the entries' indices are constants
NLSOFT_UNROLL(32)
    for (int i = S::queue; i < S::p; ++i) add_entry(z, W0, (x0[i] - off[i]) * sc[i], i);
    for (int q = 0; q < kC0; ++q) pre[ND * kC0 + q] = z[q];
NLSOFT_UNROLL(4)
    for (int j = 0; j < ND; ++j) {
      float r[kC0];
NLSOFT_UNROLL(32)
      for (int q = 0; q < kC0; ++q) r[q] = z[q];
NLSOFT_UNROLL(4)
      for (int t = j + 1; t < ND; ++t)  // u-slot t holds u(k+j-t), from x0
NLSOFT_UNROLL(8)
        for (int i = 0; i < M; ++i) {
          const int e = t * M + i, xi = (t - j - 1) * M + i;
          add_entry(r, W0, (x0[xi] - off[e]) * sc[e], e);
        }
NLSOFT_UNROLL(4)
      for (int t = j; t < ND; ++t)  // y-slot t holds y(k+j-t), from x0
NLSOFT_UNROLL(8)
        for (int i = 0; i < N; ++i) {
          const int e = ND * M + t * N + i, xi = ND * M + (t - j) * N + i;
          add_entry(r, W0, (x0[xi] - off[e]) * sc[e], e);
        }
      for (int q = 0; q < kC0; ++q) pre[j * kC0 + q] = r[q];
    }
    return ConstantInputs{pre, S::queue};
  }

  // z += x W1[e]
  __attribute__((always_inline)) static inline void add_entry(float* z, const float* W0, float x, int e) {
    const float* w = W0 + e * kC0;
NLSOFT_UNROLL(32)
    for (int q = 0; q < kC0; ++q) z[q] += x * w[q];
  }

  // A horizon as short as the MCU capacities' (hasel, tendon: N <= 4) runs
  // unrolled: each step j is inlined with j a constant, so its slot and
  // prediction counts, U's rows and every index into Y and G are constants
  // and the loops over them disappear. Costs ≈ Cap::N times the step's code
  // in flash, which an image compiling one shape has room for; msd (N up to
  // 128) and the console keep the loop.
  static constexpr int kUnrollHorizon = 4;

  static void run(const Model<Cap>& Mo, const float* x0, const float* U, int Nh, int Nc, const ConstantInputs& c,
                  float* Y, float* G, RolloutScratch<Cap>& s) {
    // A capacity of one control row admits only Nc = 1: say so, so U's rows are constants.
    const int nc = Cap::Nc == 1 ? 1 : Nc;
    if constexpr (kHeld) {
      (void)nc;
      held(Mo, x0, U, Nh, c, Y, G, s);
    } else if constexpr (Cap::N <= kUnrollHorizon) {
      unrolled(std::make_integer_sequence<int, Cap::N>{}, Mo, x0, U, Nh, nc, c, Y, G, s);
    } else {
      for (int j = 0; j < Nh; ++j) horizon_step(j, Mo, x0, U, nc, c, Y, G, s);
    }
  }

  // One control row (Cap::Nc == 1, hasel and msd) and a Dense first layer:
  // every u-slot that holds U holds the same row, so U's part of the first
  // layer is computed once per rollout, not once per slot and horizon step:
  // slot t's products, summed over the slots 0..t (at step j the slots
  // 0..min(j, ND - 1) hold U), and in the `exact` mode the same sums of the
  // weights scaled by the normalisation, which are U's tangent columns.
  // A horizon step then adds only its predictions' entries (values, and
  // their weights times their rows of G) to its row of `pre`. The steps run
  // as a loop: unrolled, their code cost ≈ 8 kB of flash per kernel for
  // the indices it turned into constants.
  static constexpr bool kHeld = Cap::Nc == 1 && !First::gru;

  static void held(const Model<Cap>& Mo, const float* x0, const float* U, int Nh, const ConstantInputs& c, float* Y,
                   float* G, RolloutScratch<Cap>& s) {
    const float* sc = Mo.in_scale();
    const float* off = Mo.in_offset();
    const float* W0 = Mo.weights(Mo.layer[0]);
    // cu[t]: the products of the u-slots 0..t; A[t][q]: their tangent, dz_q/dU
    float cu_local[kTangents ? ND : 1][Cap::width];
    float(*cu)[Cap::width] = kTangents ? cu_local : held_sums(s);
    float A[kTangents ? ND : 1][kTangents ? kC0 : 1][K];
    {
      float z[kC0];
NLSOFT_UNROLL(32)
      for (int q = 0; q < kC0; ++q) z[q] = 0.0f;
NLSOFT_UNROLL(4)
      for (int t = 0; t < ND; ++t) {
NLSOFT_UNROLL(8)
        for (int i = 0; i < M; ++i) add_entry(z, W0, (U[i] - off[t * M + i]) * sc[t * M + i], t * M + i);
NLSOFT_UNROLL(32)
        for (int q = 0; q < kC0; ++q) cu[t][q] = z[q];
        if constexpr (kTangents) {  // every index a constant, W1's rows read in order
NLSOFT_UNROLL(8)
          for (int i = 0; i < K; ++i) {  // K = Cap::m >= M: columns past M are zero
            const float si = i < M ? sc[t * M + i] : 0.0f;
            const float* w = W0 + (t * M + (i < M ? i : 0)) * kC0;
NLSOFT_UNROLL(32)
            for (int q = 0; q < kC0; ++q) A[t][q][i] = (t > 0 ? A[t - 1][q][i] : 0.0f) + si * w[q];
          }
        }
      }
    }
    horizon(Mo, x0, Nh, c, cu, A, Y, G, s);
  }

  // Where a `values` rollout leaves its cu for the stencil: in the tangent
  // buffers, which a rollout without tangents does not use (no RAM of its
  // own), when they hold ND rows of sums (rollout.hpp, RolloutScratch::held).
  static float (*held_sums(RolloutScratch<Cap>& s))[Cap::width] {
    if constexpr (2 * K >= ND) {
      return reinterpret_cast<float(*)[Cap::width]>(&s.T[0][0][0]);
    } else {
      static_assert(RolloutScratch<Cap>::kHeldRows >= ND, "the scratch holds ND rows of sums");
      return s.held;
    }
  }

  // The fd stencil's rollout: U + delta e_a changes the u-slots' products
  // by delta times input a's weights (scaled), so only those are added to
  // the sums the `values` rollout at U left in s.cu; the same horizon runs
  // on them. (Rounding differs from a rollout at U + delta e_a by a few
  // ulps of the first layer's sums, far below what the stencil resolves.)
  static void stencil(const Model<Cap>& Mo, const float* x0, int Nh, const ConstantInputs& c, int a, float delta,
                      float* Y, RolloutScratch<Cap>& s) {
    static_assert(!kTangents, "the stencil runs values");
    const float* sc = Mo.in_scale();
    const float* W0 = Mo.weights(Mo.layer[0]);
    float cu[ND][Cap::width];
    float d[kC0];
NLSOFT_UNROLL(32)
    for (int q = 0; q < kC0; ++q) d[q] = 0.0f;
    for (int t = 0; t < ND; ++t) {
      add_entry(d, W0, delta * sc[t * M + a], t * M + a);
NLSOFT_UNROLL(32)
      for (int q = 0; q < kC0; ++q) cu[t][q] = held_sums(s)[t][q] + d[q];
    }
    const float A[1][1][K] = {};
    horizon(Mo, x0, Nh, c, cu, A, Y, nullptr, s);
  }

  template <class ATab>
  __attribute__((always_inline)) static inline void horizon(const Model<Cap>& Mo, const float* x0, int Nh,
                                                            const ConstantInputs& c, const float (*cu)[Cap::width],
                                                            const ATab& A, float* Y, float* G,
                                                            RolloutScratch<Cap>& s) {
    const float* sc = Mo.in_scale();
    const float* off = Mo.in_offset();
    const float* W0 = Mo.weights(Mo.layer[0]);
    const float* os = Mo.out_scale();
    const float* oo = Mo.out_offset();
    constexpr int kU = ND * M;  // first y-queue entry
    for (int j = 0; j < Nh; ++j) {
      const int preds = j < ND ? j : ND;  // y-slots holding predictions
      const int full = j < ND ? j : ND - 1;  // u-slots 0..full hold U
      const float* prow = c.pre + (j < ND ? j : ND) * kC0;
      float z[kC0];
NLSOFT_UNROLL(32)
      for (int q = 0; q < kC0; ++q) z[q] = prow[q] + cu[full][q];
      for (int t = 0; t < preds; ++t) {  // y-slot t holds y_hat(k+j-t)
        const float* y = Y + (j - t - 1) * N;
        const int e0 = kU + t * N;
NLSOFT_UNROLL(8)
        for (int i = 0; i < N; ++i) add_entry(z, W0, (y[i] - off[e0 + i]) * sc[e0 + i], e0 + i);
      }
      float slope[S::layers][Cap::width];
      float* v = s.v[0];
NLSOFT_UNROLL(32)
      for (int q = 0; q < kC0; ++q) v[q] = z[q];
      detail::activate_fixed<kC0, First::act>(Mo.layer[0].act, v, slope[0]);
      const float(*T1)[K] = s.T[0];
      if constexpr (kTangents) {
        if (preds == 0) T1 = A[full];  // no prediction enters yet: the tangent is U's alone
        for (int q = 0; q < kC0 && preds > 0; ++q) {
          // a unit that is off (ReLU) passes no tangent: jacobian_rows skips it
          if (slope[0][q] == 0.0f) continue;
          float acc[K];
NLSOFT_UNROLL(8)
          for (int a = 0; a < K; ++a) acc[a] = A[full][q][a];
          for (int t = 0; t < preds; ++t) {  // a prediction enters with its row of G
            const int e0 = kU + t * N;
            const float* g = G + (j - t - 1) * N * K;
NLSOFT_UNROLL(8)
            for (int i = 0; i < N; ++i)
              detail::tangent_axpy<K>(acc, sc[e0 + i] * W0[(e0 + i) * kC0 + q], g + i * K);
          }
          detail::tangent_scale<K>(s.T[0][q], acc, 1.0f);
        }
      }
      int cur = 0;
      if constexpr (sizeof...(Rest) > 0) cur = layers<First::units, Rest...>(Mo, 1, s, cur, slope);
NLSOFT_UNROLL(8)
      for (int i = 0; i < N; ++i) {
        const int r = j * N + i;
        const float prev = j > 0 ? Y[r - N] : x0[kU + i];
        Y[r] = s.v[cur][i] * os[i] + oo[i] + (Mo.residual ? prev : 0.0f);
      }
      if constexpr (kTangents) jacobian_rows(Mo, slope, T1, G + j * N * K, j > 0);
    }
  }

  template <int... J>
  __attribute__((always_inline)) static inline void unrolled(std::integer_sequence<int, J...>, const Model<Cap>& Mo,
                                                             const float* x0, const float* U, int Nh, int Nc,
                                                             const ConstantInputs& c, float* Y, float* G,
                                                             RolloutScratch<Cap>& s) {
    (void)((J < Nh && (horizon_step(J, Mo, x0, U, Nc, c, Y, G, s), true)) && ...);
  }

  // Step j of the horizon: y_hat(k+j+1) and, with tangents, its rows of G.
  __attribute__((always_inline)) static inline void horizon_step(int j, const Model<Cap>& Mo, const float* x0,
                                                                 const float* U, int Nc, const ConstantInputs& c,
                                                                 float* Y, float* G, RolloutScratch<Cap>& s) {
    const float* sc = Mo.in_scale();
    const float* off = Mo.in_offset();
    const float* W0 = Mo.weights(Mo.layer[0]);
    const float* os = Mo.out_scale();
    const float* oo = Mo.out_offset();
    constexpr int kU = ND * M;  // first y-queue entry
    {
      // ---- first layer: z = pre_j + the entries of x(k+j) that hold U or
      // a prediction (Algorithm 1; the rest is in pre_j, see constant()) ----
      const int preds = j < ND ? j : ND;          // y-slots holding predictions
      const int slots = j + 1 < ND ? j + 1 : ND;  // u-slots holding U
      float* z = s.v[0];
      float zr[kC0];
      const float* prow = c.pre + (j < ND ? j : ND) * kC0;
NLSOFT_UNROLL(32)
      for (int q = 0; q < kC0; ++q) zr[q] = prow[q];
NLSOFT_UNROLL(4)
      for (int t = 0; t < slots; ++t) {  // u-slot t holds U's row j - t
        const float* u = U + (j - t < Nc ? j - t : Nc - 1) * M;
NLSOFT_UNROLL(8)
        for (int i = 0; i < M; ++i) add_entry(zr, W0, (u[i] - off[t * M + i]) * sc[t * M + i], t * M + i);
      }
NLSOFT_UNROLL(4)
      for (int t = 0; t < preds; ++t) {  // y-slot t holds y_hat(k+j-t)
        const float* y = Y + (j - t - 1) * N;
        const int e0 = kU + t * N;
NLSOFT_UNROLL(8)
        for (int i = 0; i < N; ++i) add_entry(zr, W0, (y[i] - off[e0 + i]) * sc[e0 + i], e0 + i);
      }
NLSOFT_UNROLL(32)
      for (int q = 0; q < kC0; ++q) z[q] = zr[q];

      if constexpr (kTangents) {
        for (int q = 0; q < kC0; ++q) {  // a loop: unrolled, 5-15 units times K columns cost more flash than they save
          float acc[K];
          detail::tangent_zero<K>(acc);
          // a prediction enters with its row of G: dz += sc_e W1[e][q] dy
NLSOFT_UNROLL(4)
          for (int t = 0; t < preds; ++t) {
            const int e0 = kU + t * N;
            const float* g = G + (j - t - 1) * N * K;
NLSOFT_UNROLL(8)
            for (int i = 0; i < N; ++i)
              detail::tangent_axpy<K>(acc, sc[e0 + i] * W0[(e0 + i) * kC0 + q], g + i * K);
          }
          // U itself enters through its weight, into the columns of its row
          // of U; the row is picked among the capacity's Nc blocks so every
          // index is a constant and acc stays in registers.
NLSOFT_UNROLL(4)
          for (int t = 0; t < slots; ++t) {
            const int row = j - t < Nc ? j - t : Nc - 1;
NLSOFT_UNROLL(8)
            for (int rr = 0; rr < Cap::Nc; ++rr) {
              if (rr != row) continue;
NLSOFT_UNROLL(8)
              for (int i = 0; i < M; ++i)
                if (rr * M + i < K) acc[rr * M + i] += sc[t * M + i] * W0[(t * M + i) * kC0 + q];
            }
          }
          detail::tangent_scale<K>(s.T[0][q], acc, 1.0f);
        }
      }

      // ---- the first layer's cell, then the rest (values and slopes) ----
      float slope[S::layers][Cap::width];
      int cur = 0;
      const Layer& L0 = Mo.layer[0];
      if constexpr (First::gru) {  // its tangent, dh, forward: 5 units x 3 gates
        const float* bias_rec = L0.reset_after ? W0 + (S::p + First::units) * kC0 + kC0 : nullptr;
        detail::gru_cell<K, kTangents>(L0, bias_rec, s.v[0], s.T[0], s.v[1], s.T[1], s.live);
        cur = 1;
      } else {
        detail::activate_fixed<kC0, First::act>(L0.act, z, slope[0]);
      }
      const int t1 = cur;  // the first layer's units and their tangents: v[t1], T[t1]
      if constexpr (sizeof...(Rest) > 0) cur = layers<First::units, Rest...>(Mo, 1, s, cur, slope);

      // ---- output: y = y_net out_scale + out_offset (+ y(k+j) if residual) ----
NLSOFT_UNROLL(8)
      for (int i = 0; i < N; ++i) {
        const int r = j * N + i;
        const float prev = j > 0 ? Y[r - N] : x0[kU + i];
        Y[r] = s.v[cur][i] * os[i] + oo[i] + (Mo.residual ? prev : 0.0f);
      }
      if constexpr (kTangents) jacobian_rows(Mo, slope, s.T[t1], G + j * N * K, j > 0);
    }
  }

  // R2 = R W_l' diag(slope_{l-1}) for layers l = L-1 .. 1, sizes constant.
  template <int l>
  static const float* sweep(const Model<Cap>& Mo, const float (*slope)[Cap::width], float* R, float* R2) {
    if constexpr (l < 1) {
      return R;
    } else {
      constexpr int units[S::layers] = {First::units, Rest::units...};
      constexpr int in = units[l - 1], out = units[l];
      constexpr bool scale = !(l == 1 && First::gru);  // past a GRU, T1 is already dh
      const float* Wl = Mo.weights(Mo.layer[l]);
      // R's N x out entries stay in registers; each weight is read once for
      // all N rows, and an input that is off (ReLU, slope 0) is not summed.
      float Rr[N][out];
NLSOFT_UNROLL(4)
      for (int r = 0; r < N; ++r)
NLSOFT_UNROLL(16)
        for (int c = 0; c < out; ++c) Rr[r][c] = R[r * Cap::width + c];
NLSOFT_UNROLL(16)
      for (int i = 0; i < in; ++i) {
        const float f = scale ? slope[l - 1][i] : 1.0f;
        float acc[N];
NLSOFT_UNROLL(4)
        for (int r = 0; r < N; ++r) acc[r] = 0.0f;
        if (f != 0.0f) {
          const float* w = Wl + i * out;
NLSOFT_UNROLL(16)
          for (int c = 0; c < out; ++c) {
            const float wc = w[c];
NLSOFT_UNROLL(4)
            for (int r = 0; r < N; ++r) acc[r] += Rr[r][c] * wc;
          }
        }
NLSOFT_UNROLL(4)
        for (int r = 0; r < N; ++r) R2[r * Cap::width + i] = acc[r] * f;
      }
      return sweep<l - 1>(Mo, slope, R2, R);
    }
  }

  // Mixed mode: the chain rule through the layers past the first is swept
  // backwards, from the n outputs (R = dy/dh, n x units, starting at
  // diag(out_scale * slope)), because n = 3 rows are fewer than the K = 6
  // tangent columns a forward sweep carries through every layer; then
  // dY = R T1 with T1 the first layer's tangents, and the residual's y(k+j).
  static void jacobian_rows(const Model<Cap>& Mo, const float (*slope)[Cap::width], const float (*T1)[K], float* G,
                            bool chain) {
    constexpr int kL = S::layers;
    constexpr int units[kL] = {First::units, Rest::units...};
    float Ra[N * Cap::width], Rb[N * Cap::width];
    const float* os = Mo.out_scale();
    const float* R = Ra;
    if constexpr (First::gru) static_assert(kL > 1, "a GRU's outputs are not the model's");
    if constexpr (kL == 1) {
      for (int r = 0; r < N; ++r)
        for (int c = 0; c < N; ++c) Ra[r * Cap::width + c] = r == c ? os[r] * slope[0][r] : 0.0f;
    } else {
      // the last layer's R = diag(out_scale * slope) is diagonal: its sweep is a scaling
      constexpr int in = units[kL - 2];
      constexpr bool scale = !(kL == 2 && First::gru);
      const float* Wl = Mo.weights(Mo.layer[kL - 1]);
NLSOFT_UNROLL(4)
      for (int r = 0; r < N; ++r) {
        const float d = os[r] * slope[kL - 1][r];
NLSOFT_UNROLL(16)
        for (int i = 0; i < in; ++i)
          Ra[r * Cap::width + i] = d * Wl[i * N + r] * (scale ? slope[kL - 2][i] : 1.0f);
      }
      R = sweep<kL - 2>(Mo, slope, Ra, Rb);
    }
    // dY = R T1, a first-layer unit at a time: its tangent is read once for
    // all N rows. A Dense unit that is off has R's column zero and a
    // tangent that may not have been computed (the one-row kernel skips it).
    float acc[N][K];
NLSOFT_UNROLL(4)
    for (int r = 0; r < N; ++r) detail::tangent_zero<K>(acc[r]);
NLSOFT_UNROLL(16)
    for (int q = 0; q < units[0]; ++q) {
      if (!First::gru && slope[0][q] == 0.0f) continue;
NLSOFT_UNROLL(4)
      for (int r = 0; r < N; ++r) detail::tangent_axpy<K>(acc[r], R[r * Cap::width + q], T1[q]);
    }
NLSOFT_UNROLL(4)
    for (int r = 0; r < N; ++r) {
      float* g = G + r * K;
      detail::tangent_scale<K>(g, acc[r], 1.0f);
      if (Mo.residual && chain) detail::tangent_axpy<K>(g, 1.0f, g - N * K);
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
  // with one input (msd) U's part is a product per slot: moving it saves nothing
  if constexpr (ShapedRollout<Cap, S, false>::kHeld && Dims<Cap>::K > 1)
    k.stencil = &ShapedRollout<Cap, S, false>::stencil;
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

NLSOFT_HOT_END
