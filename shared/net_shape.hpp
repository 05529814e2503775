#pragma once
// Network shapes known at compile time. A capacity lists the shapes its
// build carries specialised kernels for (kernels.hpp): the layer sizes become
// constants, so every loop of the control step has a fixed trip count and
// unrolls, while the weights stay run-time data that an upload replaces. A
// model of another shape runs on the generic kernel where the capacity
// keeps one (the console's), and is refused where it does not (an MCU image,
// whose flash holds only the kernels it needs).
namespace nlsoft {

// Layers by their output units; the input size follows from the layer before.
template <int Units>
struct DenseLayer {
  static constexpr int units = Units, cols = Units;
  static constexpr bool gru = false;
};
// A GRU's gate pre-activations are 3 x units wide.
template <int Units>
struct GruLayer {
  static constexpr int units = Units, cols = 3 * Units;
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

}  // namespace nlsoft
