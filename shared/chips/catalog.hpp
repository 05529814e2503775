#pragma once
// Every sensor chip a rig file may name. Adding a chip: its spec in this
// folder, its driver in firmware/drivers/, a line here.
#include <cstring>

#include "shared/chips/chip_spec.hpp"
#include "shared/chips/dps310.hpp"
#include "shared/chips/dynamixel.hpp"
#include "shared/chips/lis3mdl.hpp"
#include "shared/chips/lsm303dlhc_mag.hpp"
#include "shared/chips/max1111.hpp"

namespace nlsoft::chips {

inline constexpr const ChipSpec* kCatalog[] = {&kLis3mdl,  &kLsm303dlhcMag, &kDps310,     &kMax1111,   &kRx64,
                                               &kMx28,     &kAx12a,         &kXl430W250, &kXm430W350};

// nullptr for a name no chip has: the caller reports it at its source.
inline const ChipSpec* find_chip(const char* name) {
  for (const ChipSpec* c : kCatalog)
    if (std::strcmp(c->name, name) == 0) return c;
  return nullptr;
}

}  // namespace nlsoft::chips
