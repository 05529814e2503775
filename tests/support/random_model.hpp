#pragma once
// Test support: models with random weights, owned by the holder.
#include <initializer_list>
#include <random>
#include <vector>

#include "shared/model.hpp"
#include "shared/net_shape.hpp"

namespace nlsoft::test {

struct LayerSpec {
  LayerKind kind;
  int units;
  Activation act;
  Activation rec_act = Activation::Sigmoid;
  bool reset_after = true;
};

template <class Cap>
struct OwnedModel {
  Model<Cap> model;
  std::vector<float> params;
};

// Builds a model of the given dims and layers; weights ~ U(-scale, scale),
// normalisation random but well-conditioned.
template <class Cap>
OwnedModel<Cap> random_model(int m, int n, int w, int nd, std::initializer_list<LayerSpec> layers,
                             unsigned seed, float scale = 0.5f, bool residual = false) {
  OwnedModel<Cap> o;
  Model<Cap>& M = o.model;
  M.m = uint8_t(m);
  M.n = uint8_t(n);
  M.w = uint8_t(w);
  M.nd = M.dd = uint8_t(nd);
  M.residual = residual;
  int in = M.p();
  uint32_t count = M.norm_count();
  int i = 0;
  for (const LayerSpec& s : layers) {
    Layer& L = M.layer[i++];
    L.kind = s.kind;
    L.act = s.act;
    L.rec_act = s.rec_act;
    L.reset_after = s.reset_after;
    L.in = uint16_t(in);
    L.out = uint16_t(s.units);
    count += layer_weight_count(L);
    in = s.units;
  }
  M.layer_count = uint8_t(i);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-scale, scale), pos(0.5f, 1.5f);
  o.params.resize(count);
  const int p = M.p();
  for (int k = 0; k < p; ++k) {
    o.params[k] = 0.2f * u(rng);           // in_offset
    o.params[p + k] = pos(rng);            // in_scale
  }
  for (int k = 0; k < n; ++k) {
    o.params[2 * p + k] = 0.1f * u(rng);   // out_offset
    o.params[2 * p + n + k] = pos(rng);    // out_scale
  }
  for (uint32_t k = M.norm_count(); k < count; ++k) o.params[k] = u(rng);
  M.params = o.params.data();
  M.param_count = count;
  return o;
}

// A random model of a compile-time shape (net_shape.hpp): hidden layers
// use `hidden`, the last `out`; a GRU first layer gets sigmoid gates.
template <class Cap, class S>
struct ShapeModel;
template <class Cap, int M, int N, int W, int ND, class First, class... Rest>
struct ShapeModel<Cap, NetShape<M, N, W, ND, First, Rest...>> {
  static OwnedModel<Cap> make(unsigned seed, Activation hidden, Activation out, float scale = 0.6f,
                              bool residual = false) {
    constexpr int count = 1 + int(sizeof...(Rest));
    const int units[] = {First::units, Rest::units...};
    const LayerKind kinds[] = {First::kind, Rest::kind...};
    const int fixed[] = {First::act, Rest::act...};  // a shape that fixes an activation gets it
    LayerSpec specs[count];
    for (int l = 0; l < count; ++l) {
      const Activation act = fixed[l] != kActivationAtRunTime ? Activation(uint8_t(fixed[l]))
                             : l + 1 == count                 ? out
                                                              : hidden;
      specs[l] = LayerSpec{kinds[l], units[l], act, Activation::Sigmoid,
                           seed % 2 == 0};
    }
    if constexpr (count == 1) return random_model<Cap>(M, N, W, ND, {specs[0]}, seed, scale, residual);
    if constexpr (count == 2) return random_model<Cap>(M, N, W, ND, {specs[0], specs[1]}, seed, scale, residual);
    if constexpr (count == 3)
      return random_model<Cap>(M, N, W, ND, {specs[0], specs[1], specs[2]}, seed, scale, residual);
    static_assert(count <= 3, "extend ShapeModel for deeper shapes");
  }
};

// The first shape a capacity ships kernels for.
template <class List>
struct FirstShape;
template <class S, class... More>
struct FirstShape<ShapeList<S, More...>> {
  using type = S;
};

}  // namespace nlsoft::test
