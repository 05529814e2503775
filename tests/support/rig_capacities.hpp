#pragma once
// Test support: the capacities an image of each shipped rig is generated
// with (shared/capacity.hpp's rules, the rig's dimensions and horizons, its
// model's one shape), written out so typed tests run the MCU code paths of
// those sizes on the host, and benchmarks measure them.
#include "shared/capacity.hpp"

namespace nlsoft {

// A generated image's capacity for one shape: the shape's dimensions and
// buffers, horizons N and Nc, room for `kLayers` layers (at least the
// shape's).
template <class Shape, int kN, int kNc, int kLayers = Shape::layers>
struct OneShapeCapacity {
  static constexpr int m = Shape::m, n = Shape::n, w = Shape::w, nd = Shape::nd;
  static constexpr int N = kN, Nc = kNc;
  static constexpr int width = ShapeNeeds<Shape>::width, layers = kLayers, weights = ShapeNeeds<Shape>::weights;
  using Shapes = ShapeList<Shape>;
  static constexpr bool generic = false;
};

// Tight fits for the paper's three rigs.
// msd: the paper's Nc = 1 (one unknown: the tangent arrays are a single
// column) and room for our N = 100.
struct MsdCapacity {
  static constexpr int m = 1, n = 1, w = 0, nd = 2;
  static constexpr int N = 128, Nc = 1;
  static constexpr int width = 16, layers = 4, weights = 512;
  using Shapes = ShapeList<MsdShape>;
  static constexpr bool generic = false;
};
// hasel: one network shape per image, its platform's own, so the image's
// flash holds one kernel and its RAM the buffers of that shape alone. The
// default image runs our 36 -> 5 -> 5 -> 3 (233 weights, app/models);
// the authors' published Dense 36 -> 10 -> 5 -> 3 (443 weights) gets an image
// of its own (NLSOFT_M4_HASEL_SHAPE=authors, firmware/ports/cortex-m/images.cmake).
struct HaselCapacity : OneShapeCapacity<HaselShape, 4, 1, 4> {};
struct HaselAuthorsCapacity : OneShapeCapacity<HaselAuthorsShape, 4, 1, 4> {};
struct TendonCapacity {
  static constexpr int m = 2, n = 3, w = 11, nd = 2;
  static constexpr int N = 4, Nc = 3;
  static constexpr int width = 16, layers = 4, weights = 512;
  using Shapes = ShapeList<TendonShape>;
  static constexpr bool generic = false;
};

}  // namespace nlsoft
