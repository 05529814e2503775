#pragma once
// What differs between images: the rig (kRig), the capacity sized for it
// with its model's one network shape (Cap), the simulated plant of the HIL
// build (Plant, when the rig has one) and, on stm32f4, the rig's pins: all
// in nlsoft_rig.hpp, generated from the image's rig file (`nlsoft-console
// firmware build --rig`, app/firmware/image_header.cpp) and found on the
// image's include path (images.cmake). Here: what follows from those.
#include <cstddef>
#include <cstdint>

#include "nlsoft_rig.hpp"
#include "shared/model_file.hpp"

namespace nlsoft::fw::cortex_m {

// Transmit ring: one full telemetry frame above the reserve for replies.
constexpr size_t kTxCapacity = 512;

// A model file of the largest size the capacity admits. An upload is staged
// whole before it replaces the built-in model, and then runs where it lies
// (firmware.hpp).
constexpr size_t kModelFileMax = model_file_max<Cap>();

// Uploaded reference tables: a short path of points (the built-in references
// are computed on the fly and need none of this).
constexpr uint32_t kTablePoints = 64;
constexpr uint32_t kTableFloats = kTablePoints * uint32_t(Cap::n);
constexpr size_t kTableFileMax = 8 + 4 * size_t(kTableFloats);

}  // namespace nlsoft::fw::cortex_m
