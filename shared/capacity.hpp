#pragma once
// Compile-time capacities. Every array in the controller is sized from one of
// these structs, so a build states its worst case once and the linker map shows
// the RAM it costs. A firmware image's is generated from its rig file, sized
// to the rig and its one network shape (app/firmware/image_header.cpp); the
// console uses HostCapacity, which fits every rig a rig file may describe
// (host/rig/rig.hpp RigCapacity: n <= 6, w <= 32).
//
// A capacity struct provides:
//   m, n, w      max actuators, outputs, sensor channels        (paper: m, n, w)
//   nd           max history length for u and y                 (paper: n_d = d_d)
//   N, Nc        max prediction and control horizon             (paper: N, N_c)
//   width        max layer width (a GRU counts 3 x units)
//   layers       max layer count
//   weights      max total weight + bias count of a model
//   Shapes       the network shapes with specialised kernels (net_shape.hpp)
//   generic      whether other shapes run on the generic kernel or are refused
#include <cstdint>

#include "shared/net_shape.hpp"

namespace nlsoft {

// The dimensions that follow from a capacity.
template <class Cap>
struct Dims {
  // p = n_d m + d_d n + w, the network input length (paper, "Problem Statement")
  static constexpr int p = Cap::nd * Cap::m + Cap::nd * Cap::n + Cap::w;
  // U in R^{Nc x m}, flattened: the Newton-Raphson unknowns
  static constexpr int K = Cap::Nc * Cap::m;

 private:
  template <class... S>
  static constexpr bool inputs_fill(ShapeList<S...>) {
    return sizeof...(S) > 0 && ((S::m == Cap::m) && ...);
  }

 public:
  // Whether every model the capacity runs has exactly K unknowns (k = Nc m
  // = K): an image's does, which runs its shapes only (so m is a shape's,
  // each the capacity's) with one control row (so Nc = 1). Its solver then
  // loops over K, a constant, and the code for k < K compiles away.
  static constexpr bool full_k = !Cap::generic && Cap::Nc == 1 && inputs_fill(typename Cap::Shapes{});
  // k = Nc m, the unknowns of a problem with this Nc and m.
  static constexpr int unknowns(int Nc, int m) { return full_k ? K : Nc * m; }
};

// The shipped models' shapes (app/models/README.md) and the authors' hasel
// model (Dense 36 -> 10 -> 5 -> 3).
using MsdShape = NetShape<1, 1, 0, 2, DenseLayer<1>>;
using HaselShape = NetShape<6, 3, 18, 2, DenseLayer<5>, DenseLayer<5>, DenseLayer<3>>;
using HaselAuthorsShape = NetShape<6, 3, 18, 2, DenseLayer<10>, DenseLayer<5>, DenseLayer<3>>;
using TendonShape = NetShape<2, 3, 11, 2, GruLayer<5>, DenseLayer<5>, DenseLayer<3>>;

// nd = 32 lets a one-input, one-output system keep 32 samples of each
// history (the Wiener-Hammerstein benchmark's two third-order blocks need
// more than 4); a rig's input vector p = nd m + dd n + w stays within
// `inputs`, the widest rig with 4 samples of history (4 8 + 4 6 + 32), so a
// narrow rig trades width for history and a wide one keeps short histories.
struct HostCapacity {
  static constexpr int m = 8, n = 6, w = 32, nd = 32, inputs = 88;
  static constexpr int N = 128, Nc = 4;
  static constexpr int width = 48, layers = 8, weights = 8192;
  using Shapes = ShapeList<MsdShape, HaselShape, HaselAuthorsShape, TendonShape>;
  static constexpr bool generic = true;
};

}  // namespace nlsoft
