#pragma once
// What differs between the three images: the platform, the tightest
// capacity that holds its preset and paper-sized model, the simulated plant
// of the HIL build, and the RAM given to uploads. Selected by
// NLSOFT_PLATFORM_{MSD,HASEL,TENDON} from the build. Each capacity carries
// one network shape, so an image compiles one kernel; the hasel image's is
// ours (app/models/hasel.nlsm) unless the build asks for the authors'
// (NLSOFT_HASEL_AUTHORS_SHAPE, from images.cmake's NLSOFT_M4_HASEL_SHAPE).
#include <cstddef>
#include <cstdint>

#include "shared/capacity.hpp"
#include "shared/model_file.hpp"
#include "shared/platform_id.hpp"
#include "shared/plant_hasel.hpp"
#include "shared/plant_msd.hpp"
#include "shared/plant_tendon.hpp"
#include "shared/reference_presets.hpp"
#include "shared/rig_config.hpp"

namespace nlsoft::fw::cortex_m {

#if defined(NLSOFT_PLATFORM_HASEL) && defined(NLSOFT_HASEL_AUTHORS_SHAPE)
using Cap = HaselAuthorsCapacity;
using Plant = HaselPlant;
constexpr PlatformId kPlatform = PlatformId::Hasel;
#elif defined(NLSOFT_PLATFORM_HASEL)
using Cap = HaselCapacity;
using Plant = HaselPlant;
constexpr PlatformId kPlatform = PlatformId::Hasel;
#elif defined(NLSOFT_PLATFORM_TENDON)
using Cap = TendonCapacity;
using Plant = TendonPlant;
constexpr PlatformId kPlatform = PlatformId::Tendon;
#elif defined(NLSOFT_PLATFORM_MSD)
using Cap = MsdCapacity;
using Plant = MsdPlant;
constexpr PlatformId kPlatform = PlatformId::Msd;
#else
#error "define NLSOFT_PLATFORM_MSD, NLSOFT_PLATFORM_HASEL or NLSOFT_PLATFORM_TENDON"
#endif

// The rig the image serves: dimensions, limits, defaults, start-up reference.
constexpr RigConfig kRig = shipped_rig(kPlatform);

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
