#pragma once
// A rig's reference paths: the kind and geometry of its [reference] table
// as the parameters the MCU computes the path from (shared/reference.hpp).
#include "host/rig/rig.hpp"
#include "shared/reference.hpp"

namespace nlsoft::host {

// Periodic paths take 8 s per lap at the rig's rate, Swirl holds each point
// 10 steps, Step holds each level 10 s.
RefParams rig_reference(const Rig& rig, RefKind kind);

// The kind's name as a rig file, a script and the console write it.
const char* reference_kind_name(RefKind k);

}  // namespace nlsoft::host
