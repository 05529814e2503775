#pragma once
// The learned forward model g(x) -> y_hat(k+1) (the paper's eq. 1), as data.
//
// A Model is a view: the layer table and dimensions live in it, the numbers
// (normalisation + weights) in one caller-owned float block, so the same code
// runs a model file embedded in flash (an image's model_blob.S) or one uploaded into RAM.
//
// Parameter block layout, all float32:
//   in_offset[p] in_scale[p] out_offset[n] out_scale[n]   normalisation
//   then per layer, Keras order:
//     Dense: W[in][out], b[out]                y = act(x W + b)
//     GRU:   kernel[in][3u], recurrent[u][3u], bias[3u] (reset_after = 0)
//                                              or bias[2][3u] (reset_after = 1)
//            gate column order z | r | h, as Keras stores them.
// The network sees x_net = (x - in_offset) * in_scale and produces
// y = y_net * out_scale + out_offset (+ y(k) when `residual`: the network then
// predicts the transition y(k+1) - y(k), as the paper trains it).
#include <cstdint>

#include "shared/activation.hpp"
#include "shared/capacity.hpp"
#include "shared/layer_kind.hpp"
#include "shared/status.hpp"

namespace nlsoft {

struct Layer {
  LayerKind kind = LayerKind::Dense;
  Activation act = Activation::Linear;       // Dense output / GRU candidate
  Activation rec_act = Activation::Sigmoid;  // GRU gates z, r
  bool reset_after = true;                   // GRU only
  uint16_t in = 0, out = 0;                  // out = units for a GRU
  uint32_t offset = 0;                       // first weight in the block
};

inline uint32_t layer_weight_count(const Layer& L) {
  return layer_weights(L.kind, uint32_t(L.in), uint32_t(L.out), L.reset_after);
}

template <class Cap>
struct Model {
  uint8_t m = 0, n = 0, w = 0, nd = 0, dd = 0;
  bool residual = false;
  uint8_t layer_count = 0;
  Layer layer[Cap::layers] = {};
  const float* params = nullptr;  // normalisation + weights, see layout above
  uint32_t param_count = 0;
  uint32_t hash = 0;  // CRC-32 of the model file, reported in INFO

  int p() const { return nd * m + dd * n + w; }
  const float* in_offset() const { return params; }
  const float* in_scale() const { return params + p(); }
  const float* out_offset() const { return params + 2 * p(); }
  const float* out_scale() const { return params + 2 * p() + n; }
  uint32_t norm_count() const { return uint32_t(2 * p() + 2 * n); }
  const float* weights(const Layer& L) const { return params + L.offset; }
};

// Checks the layer chain against the capacity and assigns each layer's
// offset into the parameter block. Reads no parameter values.
template <class Cap>
Status check_model_shape(Model<Cap>& M) {
  if (M.m == 0 || M.n == 0 || M.nd == 0 || M.dd == 0) return Status::WrongSize;
  if (M.m > Cap::m || M.n > Cap::n || M.w > Cap::w || M.nd > Cap::nd || M.dd > Cap::nd)
    return Status::TooLarge;
  if (M.layer_count == 0) return Status::WrongSize;
  if (M.layer_count > Cap::layers) return Status::TooLarge;
  uint32_t offset = M.norm_count();
  int width = M.p();
  for (int i = 0; i < M.layer_count; ++i) {
    Layer& L = M.layer[i];
    if (!layer_kind_known(uint8_t(L.kind))) return Status::UnknownId;
    if (!activation_valid(uint8_t(L.act)) || !activation_valid(uint8_t(L.rec_act))) return Status::UnknownId;
    if (L.in != width || L.out == 0) return Status::Inconsistent;
    const int buf = layer_columns(L.kind, L.out);
    if (buf > Cap::width) return Status::TooLarge;
    L.offset = offset;
    offset += layer_weight_count(L);
    width = L.out;
  }
  if (width != M.n) return Status::Inconsistent;
  if (offset > uint32_t(Cap::weights) + M.norm_count()) return Status::TooLarge;
  if (offset != M.param_count) return Status::WrongSize;
  return Status::Ok;
}

// Shape check plus every number finite, so the controller never has to.
template <class Cap>
Status finalize_model(Model<Cap>& M) {
  const Status s = check_model_shape(M);
  if (s != Status::Ok) return s;
  if (M.params == nullptr) return Status::BadFormat;
  for (uint32_t i = 0; i < M.param_count; ++i) {
    const float v = M.params[i];
    if (!(v - v == 0.0f)) return Status::NotFinite;
  }
  return Status::Ok;
}

}  // namespace nlsoft
