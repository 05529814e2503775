#pragma once
// Test support: models with random weights, owned by the holder.
#include <initializer_list>
#include <random>
#include <vector>

#include "shared/model.hpp"

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

}  // namespace nlsoft::test
