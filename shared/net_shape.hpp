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
// A GRU's gate pre-activations are 3 x units wide; its activations are
// always read from the model.
template <int Units>
struct GruLayer {
  static constexpr int units = Units, cols = layer_columns(LayerKind::Gru, Units),
                       act = kActivationAtRunTime;
  static constexpr LayerKind kind = LayerKind::Gru;
  static constexpr bool gru = true;
};

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
// (model.hpp's layer_weight_count, GRU biases reset_after) and its widest
// layer buffer (a GRU's 3 x units), so an image built for one shape
// reserves no RAM beyond it.
template <class S>
struct ShapeNeeds;
template <int M, int N, int W, int ND, class First, class... Rest>
struct ShapeNeeds<NetShape<M, N, W, ND, First, Rest...>> {
 private:
  static constexpr int sum() {
    const int cols[] = {First::cols, Rest::cols...};
    const int units[] = {First::units, Rest::units...};
    const bool gru[] = {First::gru, Rest::gru...};
    int in = ND * (M + N) + W, total = 0;
    for (int l = 0; l < 1 + int(sizeof...(Rest)); ++l) {
      total += gru[l] ? in * cols[l] + units[l] * cols[l] + 2 * cols[l] : in * units[l] + units[l];
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
