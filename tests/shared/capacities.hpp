#pragma once
// Every capacity a build ships (the console's and the three firmware images'),
// for typed tests: the MCU code paths run here on the host, under the
// sanitizers too.
#include <gtest/gtest.h>

#include "shared/capacity.hpp"

namespace nlsoft::test {

using ShippedCapacities = ::testing::Types<HostCapacity, HaselCapacity, HaselAuthorsCapacity, TendonCapacity, MsdCapacity>;

// Names the typed instances after the capacity.
struct CapacityName {
  template <class Cap>
  static std::string GetName(int) {
    if (std::is_same_v<Cap, HostCapacity>) return "Host";
    if (std::is_same_v<Cap, HaselCapacity>) return "Hasel";
    if (std::is_same_v<Cap, HaselAuthorsCapacity>) return "HaselAuthors";
    if (std::is_same_v<Cap, TendonCapacity>) return "Tendon";
    return "Msd";
  }
};

}  // namespace nlsoft::test
