#pragma once
// Network shapes known at compile time. A capacity lists the shapes its
// build carries specialised kernels for (kernels.hpp): the layer sizes become
// constants, so every loop of the control step has a fixed trip count and
// unrolls, while the weights stay run-time data that an upload replaces. A
// model of another shape runs on the generic kernel where the capacity
// keeps one (the console's), and is refused where it does not (an MCU image,
// whose flash holds only the kernels it needs).
#include "shared/activation.hpp"
#include "shared/layer_kind.hpp"

namespace nlsoft {

// A layer's activation as its kernel knows it: read from the model at run
// time, or fixed when the shape is compiled (an image that can take no
// upload runs the model it was built with, so the kernel keeps only that
// activation's code: on hasel's image the tanh branches of five layer
// sites were ~5 kB of flash, and no test of the kind remains per layer).
inline constexpr int kActivationAtRunTime = -1;

// Layers by their output units; the input size follows from the layer
// before. Act: int(Activation::...), or kActivationAtRunTime.
template <int Units, int Act = kActivationAtRunTime>
struct DenseLayer {
  static constexpr int units = Units, cols = Units, act = Act;
  static constexpr LayerKind kind = LayerKind::Dense;
  static constexpr bool gru = false;
};
// A layer of a kind whose activations are its own (layer_kind.hpp: a
// GRU's), read from the model at run time; its columns are its kind's gates
// x units (a GRU's gate pre-activations, 3 x units). One template for every
// such kind, so a new kind needs none of its own here.
template <LayerKind K, int Units>
struct KindLayer {
  static_assert(!LayerKindRow<K>::free_activation, "a kind that takes a chosen activation is a DenseLayer");
  static constexpr int units = Units, cols = layer_columns(K, Units), act = kActivationAtRunTime;
  static constexpr LayerKind kind = K;
  static constexpr bool gru = K == LayerKind::Gru;
};
template <int Units>
using GruLayer = KindLayer<LayerKind::Gru, Units>;

// m actuators, n outputs, w sensor channels, nd = dd history length
// (paper: n_d = d_d), then the layers, the first one first.
template <int M, int N, int W, int ND, class First, class... Rest>
struct NetShape {
  static constexpr int m = M, n = N, w = W, nd = ND;
  static constexpr int queue = ND * (M + N);  // u- and y-queue entries of x
  static constexpr int p = queue + W;
  static constexpr int layers = 1 + int(sizeof...(Rest));
};

template <class... Shapes>
struct ShapeList {};

// What a model of shape S needs of a capacity: its weight and bias count
// (layer_kind.hpp's layer_weights, a GRU's biases reset_after) and its widest
// layer buffer (a GRU's 3 x units), so an image built for one shape
// reserves no RAM beyond it.
template <class S>
struct ShapeNeeds;
template <int M, int N, int W, int ND, class First, class... Rest>
struct ShapeNeeds<NetShape<M, N, W, ND, First, Rest...>> {
 private:
  static constexpr int sum() {
    const int units[] = {First::units, Rest::units...};
    const LayerKind kinds[] = {First::kind, Rest::kind...};
    int in = ND * (M + N) + W, total = 0;
    for (int l = 0; l < 1 + int(sizeof...(Rest)); ++l) {
      total += layer_weights(kinds[l], in, units[l], true);
      in = units[l];
    }
    return total;
  }
  static constexpr int widest() {
    const int cols[] = {First::cols, Rest::cols...};
    int w = 0;
    for (int c : cols) w = c > w ? c : w;
    return w;
  }

 public:
  static constexpr int weights = sum(), width = widest();
};

}  // namespace nlsoft
