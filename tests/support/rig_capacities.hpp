#pragma once
// Test support: the capacities an image of each shipped rig is generated
// with (shared/capacity.hpp's rules, the rig's dimensions and horizons, its
// model's one shape), written out so typed tests run the MCU code paths of
// those sizes on the host, and benchmarks measure them.
#include "shared/capacity.hpp"

namespace nlsoft {

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
struct HaselCapacity {
  static constexpr int m = 6, n = 3, w = 18, nd = 2;
  static constexpr int N = 4, Nc = 1;
  static constexpr int width = ShapeNeeds<HaselShape>::width, layers = 4, weights = ShapeNeeds<HaselShape>::weights;
  using Shapes = ShapeList<HaselShape>;
  static constexpr bool generic = false;
};
struct HaselAuthorsCapacity {
  static constexpr int m = 6, n = 3, w = 18, nd = 2;
  static constexpr int N = 4, Nc = 1;
  static constexpr int width = ShapeNeeds<HaselAuthorsShape>::width, layers = 4;
  static constexpr int weights = ShapeNeeds<HaselAuthorsShape>::weights;
  using Shapes = ShapeList<HaselAuthorsShape>;
  static constexpr bool generic = false;
};
struct TendonCapacity {
  static constexpr int m = 2, n = 3, w = 11, nd = 2;
  static constexpr int N = 4, Nc = 3;
  static constexpr int width = 16, layers = 4, weights = 512;
  using Shapes = ShapeList<TendonShape>;
  static constexpr bool generic = false;
};

}  // namespace nlsoft
