// INFO's platform byte: the number a shipped rig's images send (protocol/
// PROTOCOL.md, INFO), given by its rig file's info_platform. Which rig a
// number stands for is the rig files' business, not the code's: the
// console finds it by reading them (host/rig/rig_catalog.hpp).
#pragma once

#include <cstdint>

namespace nlsoft {

// The numeric values travel on the wire: append, never renumber; tied to
// protocol::Platform where the two meet (firmware/core/firmware.hpp).
// Custom: a rig known only by its rig file (its name and hash travel apart).
enum class PlatformId : uint8_t { Msd = 0, Hasel = 1, Tendon = 2, Custom = 0xFF };

// The numbers the protocol assigns (0 .. kPlatformCount - 1).
constexpr int kPlatformCount = 3;

}  // namespace nlsoft
