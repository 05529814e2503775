#pragma once
// Every capacity a build ships (the console's and the three firmware images'),
// for typed tests: the MCU code paths run here on the host, under the
// sanitizers too.
#include <gtest/gtest.h>

#include "../support/rig_capacities.hpp"

namespace nlsoft::test {

// A generated image of a one-input rig with a long memory (nd = 16 > 2 Nc m):
// its kernels keep the first layer's sums beside the tangent buffers.
using LongHistoryShape = NetShape<1, 1, 0, 16, DenseLayer<16>, DenseLayer<1>>;
struct LongHistoryCapacity : OneShapeCapacity<LongHistoryShape, 16, 1> {};

// A generated image that takes no model upload (image_header.cpp): hasel's
// shape with its activations compiled in, so its kernels keep only those,
// and one control row, so its solver's unknowns are K. tanh rather than
// the shipped model's ReLU: the solver's suites ask for a smooth model.
using HaselFixedShape = NetShape<6, 3, 18, 2, DenseLayer<5, int(Activation::Tanh)>,
                                 DenseLayer<5, int(Activation::Tanh)>, DenseLayer<3, int(Activation::Linear)>>;
struct HaselFixedCapacity : OneShapeCapacity<HaselFixedShape, 3, 1> {};

using ShippedCapacities = ::testing::Types<HostCapacity, HaselCapacity, HaselAuthorsCapacity, TendonCapacity, MsdCapacity,
                                           LongHistoryCapacity, HaselFixedCapacity>;

// Names the typed instances after the capacity.
struct CapacityName {
  template <class Cap>
  static std::string GetName(int) {
    if constexpr (std::is_same_v<Cap, HostCapacity>) return "Host";
    else if constexpr (std::is_same_v<Cap, HaselCapacity>) return "Hasel";
    else if constexpr (std::is_same_v<Cap, HaselAuthorsCapacity>) return "HaselAuthors";
    else if constexpr (std::is_same_v<Cap, TendonCapacity>) return "Tendon";
    else if constexpr (std::is_same_v<Cap, MsdCapacity>) return "Msd";
    else if constexpr (std::is_same_v<Cap, LongHistoryCapacity>) return "LongHistory";
    else {
      static_assert(std::is_same_v<Cap, HaselFixedCapacity>, "name every capacity");
      return "HaselFixed";
    }
  }
};

}  // namespace nlsoft::test
