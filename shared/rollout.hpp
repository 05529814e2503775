#pragma once
// The controller's horizon rollout (paper, "Problem Statement"): the
// predictions Y_hat = [y_hat(k+1) ... y_hat(k+N)], each fed back into the
// y-queue of the next input vector, U's rows past Nc repeating the last; and,
// for the `exact` mode, their Jacobian G = dY_hat/dU by the chain rule, carried
// forward through the layers and the recursion together with the values
// (forward mode: each unit carries its K partial derivatives, its tangent).
//
// It computes what predict_horizon (horizon.hpp) and the reference jets
// (derivatives.hpp) compute, and tests hold it to them, but at the cost of
// the arithmetic itself:
//  - the first layer's response to the sensor signals l(k) and its bias is
//    computed once per control step (ConstantInputs) and only the queue
//    entries are multiplied in each rollout step;
//  - U enters through rows of W1: a u-slot holding U_{r,c} adds its weight
//    row to tangent column r m + c, no product needed; a y-slot holding a
//    prediction adds its weights times that prediction's row of G;
//  - the tangent loops run over the capacity's K, a compile-time count, so
//    they unroll; a unit whose slope is zero (a ReLU that is off) carries no
//    tangent and its row is skipped in the next layer;
//  - activations use the fast exp of activation.hpp.
// GRU layers run as in forward.hpp with a zero initial state (the paper's
// single-timestep use).
#include "shared/hot_path.hpp"
#include "shared/activation.hpp"
#include "shared/forward.hpp"

// The control step's hot code is compiled for speed even in images built
// for size (-Os): measured on the Cortex-M4F, -Os here costs 2.3x the
// instructions per step (the accessors and the unrolled tangent loops are
// not inlined), while the rest of an image gains nothing from -O2.
NLSOFT_HOT_BEGIN

namespace nlsoft {

// Caller-owned unit buffers of one rollout, nothing else; values and, in the
// `exact` mode, tangents of the layer being computed and the one before.
template <class Cap>
struct RolloutScratch {
  static constexpr int K = Dims<Cap>::K;
  // u- and y-queue entries; only the generic kernel keeps them (kernels.hpp)
  static constexpr int kQueue = Cap::generic ? Cap::nd * (Cap::m + Cap::n) : 1;
  float v[2][Cap::width];
  float T[2][Cap::width][K];
  uint8_t live[Cap::width];    // units of the last cell whose tangent is not zero
  float xn[kQueue];            // normalised queue entries of the rollout step
  int16_t src[kQueue];         // their source: >= 0 a U column, < -1 a prediction row (-2 - row), -1 x0
  int16_t on_u[kQueue];        // the entries holding U, and those holding predictions
  int16_t on_y[kQueue];
  // Where a `values` rollout leaves its first-layer sums for the stencil
  // (kernels.hpp): in T, which such a rollout does not use, unless the
  // history is longer than T holds rows (nd > 2K: a one-input rig with a
  // long memory), and then here.
  static constexpr int kHeldRows = Cap::nd > 2 * K ? Cap::nd : 1;
  float held[kHeldRows][Cap::width];
};

namespace detail {

// The K-wide tangent arithmetic, unrolled: K is a compile-time count, and
// the accumulators stay in registers (the M4F has 32 single-precision ones).
template <int K>
inline void tangent_axpy(float* acc, float w, const float* t) {
NLSOFT_UNROLL(32)
  for (int a = 0; a < K; ++a) acc[a] += w * t[a];
}
template <int K>
inline void tangent_scale(float* out, const float* acc, float f) {
NLSOFT_UNROLL(32)
  for (int a = 0; a < K; ++a) out[a] = acc[a] * f;
}
template <int K>
inline void tangent_zero(float* acc) {
NLSOFT_UNROLL(32)
  for (int a = 0; a < K; ++a) acc[a] = 0.0f;
}

// Dense layer past the first, one output unit at a time so its value and
// tangent accumulate in registers: y_j = act(b_j + sum_i x_i W_ij),
// dy_j = act'(.) sum_i W_ij dx_i over the inputs whose tangent is live.
template <int K, int kWidth, bool kTangents>
inline void dense_layer(const Layer& L, const float* W, const float* x, const float (*Tx)[K], uint8_t* live,
                        float* y, float (*Ty)[K]) {
  const int cols = L.out;
  const float* bias = W + L.in * cols;
  uint8_t idx[kWidth];
  int nl = 0;
  if constexpr (kTangents)
    for (int i = 0; i < L.in; ++i)
      if (live[i]) idx[nl++] = uint8_t(i);
  for (int j = 0; j < cols; ++j) y[j] = bias[j];
  for (int i = 0; i < L.in; ++i) {  // row by row: W is stored [in][out]
    const float xi = x[i];
    const float* w = W + i * cols;
    for (int j = 0; j < cols; ++j) y[j] += xi * w[j];
  }
  for (int j = 0; j < cols; ++j) {
    const ActSlope f = activate_slope(L.act, y[j]);
    y[j] = f.f;
    if constexpr (kTangents) {
      float acc[K];
      tangent_zero<K>(acc);
      for (int e = 0; e < nl; ++e) tangent_axpy<K>(acc, W[idx[e] * cols + j], Tx[idx[e]]);
      tangent_scale<K>(Ty[j], acc, f.df);
      live[j] = f.df != 0.0f;  // idx holds the inputs' flags already
    }
  }
}

// GRU layer past the first: gate pre-activations g = b + x W (3u), then the cell.
template <int K, bool kTangents>
inline void gru_affine(const Layer& L, const float* W, const float* x, const float (*Tx)[K], const uint8_t* live,
                       float* g, float (*Tg)[K]) {
  const int cols = 3 * L.out;
  const float* bias = W + (L.in + L.out) * cols;
  for (int j = 0; j < cols; ++j) {
    float z = bias[j];
    for (int i = 0; i < L.in; ++i) z += x[i] * W[i * cols + j];
    g[j] = z;
    if constexpr (kTangents) {
      float acc[K];
      tangent_zero<K>(acc);
      for (int i = 0; i < L.in; ++i)
        if (live[i]) tangent_axpy<K>(acc, W[i * cols + j], Tx[i]);
      tangent_scale<K>(Tg[j], acc, 1.0f);
    }
  }
}

// GRU cell with zero initial state (forward.hpp's gru with h_prev = 0) on
// the gate pre-activations g = [z | r | h] (3u): h = (1 - z) h~.
template <int K, bool kTangents>
inline void gru_cell(const Layer& L, const float* bias_rec, const float* g, const float (*Tg)[K], float* h,
                     float (*Th)[K], uint8_t* live) {
  const int u = L.out;
  for (int j = 0; j < u; ++j) {
    const float rz = bias_rec ? bias_rec[j] : 0.0f, rr = bias_rec ? bias_rec[u + j] : 0.0f;
    const float rh = bias_rec ? bias_rec[2 * u + j] : 0.0f;
    const ActSlope z = activate_slope(L.rec_act, g[j] + rz);
    const ActSlope r = activate_slope(L.rec_act, g[u + j] + rr);
    // reset_after: h~ = act(x Wh + bh + r rbh); otherwise the reset gate
    // multiplies the zero state and drops out.
    const ActSlope c = activate_slope(L.act, g[2 * u + j] + (L.reset_after ? r.f * rh : 0.0f));
    h[j] = (1.0f - z.f) * c.f;
    if constexpr (kTangents) {
      live[j] = 1;
      const float kz = -c.f * z.df, kc = (1.0f - z.f) * c.df, kr = L.reset_after ? kc * rh * r.df : 0.0f;
      float acc[K];
      tangent_scale<K>(acc, Tg[j], kz);
      tangent_axpy<K>(acc, kc, Tg[2 * u + j]);
      tangent_axpy<K>(acc, kr, Tg[u + j]);
      tangent_scale<K>(Th[j], acc, 1.0f);
    }
  }
}

// The queue entries of x(k+j) (Algorithm 1), normalised, and where each
// came from (s.src): u-slot t holds u(k+j-t), a row of U (its index) or
// x0's history (-1); y-slot t holds y(k+j-t), a prediction already made
// (-2 - its index in Y) or x0's history (-1).
template <class Cap>
__attribute__((always_inline)) inline void queue_entries(const Model<Cap>& M, const float* x0, const float* U,
                                                         const float* Y, int j, int Nc, RolloutScratch<Cap>& s) {
  const int m = M.m, n = M.n, nd = M.nd, dd = M.dd;
  const float* sc = M.in_scale();
  const float* off = M.in_offset();
  for (int t = 0; t < nd; ++t) {
    const int row = j - t;
    for (int i = 0; i < m; ++i) {
      const int e = t * m + i;
      const int col = row >= 0 ? (row < Nc ? row : Nc - 1) * m + i : -1;
      const float x = col >= 0 ? U[col] : x0[(t - j - 1) * m + i];
      s.xn[e] = (x - off[e]) * sc[e];
      s.src[e] = int16_t(col);
    }
  }
  for (int t = 0; t < dd; ++t) {
    const int row = j - t - 1;
    for (int i = 0; i < n; ++i) {
      const int e = nd * m + t * n + i;
      const float x = row >= 0 ? Y[row * n + i] : x0[nd * m + (t - j) * n + i];
      s.xn[e] = (x - off[e]) * sc[e];
      s.src[e] = int16_t(row >= 0 ? -2 - (row * n + i) : -1);
    }
  }
}

// The first layer's pre-activations into s.v[0]: z = pre + sum_e xn_e W1[e],
// and with tangents dz = sum_e sc_e W1[e] dx_e into s.T[0], from the rows
// of G of the predictions in the queue and a weight into U's own column.
template <class Cap, bool kTangents>
__attribute__((always_inline)) inline void first_layer(const Model<Cap>& M, const ConstantInputs& c,
                                                       const float* G, RolloutScratch<Cap>& s) {
  constexpr int K = Dims<Cap>::K;
  const int queue = M.nd * M.m + M.dd * M.n;
  const float* sc = M.in_scale();
  const Layer& L0 = M.layer[0];
  const int cols0 = layer_columns(L0.kind, L0.out);
  const float* W0 = M.weights(L0);
  float* z = s.v[0];
  for (int q = 0; q < cols0; ++q) z[q] = c.pre[q];
  for (int e = 0; e < queue; ++e) {  // row by row: W1 is stored [in][out]
    const float xe = s.xn[e];
    const float* w = W0 + e * cols0;
    for (int q = 0; q < cols0; ++q) z[q] += xe * w[q];
  }
  if constexpr (kTangents) {
    int nu = 0, np = 0;
    int16_t* on_u = s.on_u;
    int16_t* on_y = s.on_y;
    for (int e = 0; e < queue; ++e) {
      if (s.src[e] >= 0) on_u[nu++] = int16_t(e);
      if (s.src[e] < -1) on_y[np++] = int16_t(e);
    }
    for (int q = 0; q < cols0; ++q) {  // predictions: their rows of G
      float acc[K];
      tangent_zero<K>(acc);
      for (int i = 0; i < np; ++i) {
        const int e = on_y[i];
        tangent_axpy<K>(acc, sc[e] * W0[e * cols0 + q], G + (-2 - s.src[e]) * K);
      }
      tangent_scale<K>(s.T[0][q], acc, 1.0f);
    }
    for (int i = 0; i < nu; ++i) {  // U itself: a weight into its column, no product
      const int e = on_u[i], col = s.src[e];
      const float* w = W0 + e * cols0;
      for (int q = 0; q < cols0; ++q) s.T[0][q][col] += sc[e] * w[q];
    }
  }
}

}  // namespace detail

// Y: N x n predictions. G (exact only, else null): N n rows of K, row
// (j n + i) = dY[j][i]/dU. `c`: constant_inputs() of x0 (required).
template <class Cap, bool kTangents>
void rollout(const Model<Cap>& M, const float* x0, const float* U, int N, int Nc, const ConstantInputs& c,
             float* Y, float* G, RolloutScratch<Cap>& s) {
  constexpr int K = Dims<Cap>::K;
  const int m = M.m, n = M.n, nd = M.nd;
  const float* os = M.out_scale();
  const float* oo = M.out_offset();

  for (int j = 0; j < N; ++j) {
    detail::queue_entries(M, x0, U, Y, j, Nc, s);
    detail::first_layer<Cap, kTangents>(M, c, G, s);

    // ---- the layers' cells ----
    int cur = 0;
    for (int l = 0; l < M.layer_count; ++l) {
      const Layer& L = M.layer[l];
      const float* W = M.weights(L);
      const int cols = layer_columns(L.kind, L.out);
      if (L.kind == LayerKind::Dense) {
        if (l == 0) {  // pre-activations are in place: activate them
          for (int q = 0; q < cols; ++q) {
            const ActSlope f = activate_slope(L.act, s.v[0][q]);
            s.v[0][q] = f.f;
            if constexpr (kTangents) {
              detail::tangent_scale<K>(s.T[0][q], s.T[0][q], f.df);
              s.live[q] = f.df != 0.0f;
            }
          }
        } else {
          detail::dense_layer<K, Cap::width, kTangents>(L, W, s.v[cur], s.T[cur], s.live, s.v[1 - cur], s.T[1 - cur]);
          cur = 1 - cur;
        }
      } else {
        if (l > 0) {
          detail::gru_affine<K, kTangents>(L, W, s.v[cur], s.T[cur], s.live, s.v[1 - cur], s.T[1 - cur]);
          cur = 1 - cur;
        }
        const float* bias_rec = L.reset_after ? W + (L.in + L.out) * cols + cols : nullptr;
        detail::gru_cell<K, kTangents>(L, bias_rec, s.v[cur], s.T[cur], s.v[1 - cur], s.T[1 - cur], s.live);
        cur = 1 - cur;
      }
    }

    // ---- output: y = y_net out_scale + out_offset (+ y(k+j) if residual) ----
    for (int i = 0; i < n; ++i) {
      const int r = j * n + i;
      const float prev = j > 0 ? Y[r - n] : x0[nd * m + i];
      Y[r] = s.v[cur][i] * os[i] + oo[i] + (M.residual ? prev : 0.0f);
      if constexpr (kTangents) {
        float* g = G + r * K;
        detail::tangent_scale<K>(g, s.T[cur][i], os[i]);
        if (M.residual && j > 0) detail::tangent_axpy<K>(g, 1.0f, g - n * K);
      }
    }
  }
}

}  // namespace nlsoft

NLSOFT_HOT_END
