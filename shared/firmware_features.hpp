#pragma once
// The services an image may leave out, as the rig file names them
// ([firmware] features, docs/rig-file.md). Every image has the minimum:
// the link, the parameters, closed-loop runs on the compiled-in references
// (Infinity, Pringle, Swirl, steps) and telemetry. Each entry below is one
// service more; an image built without it has none of its code, INFO has
// none of its capability bits, and its requests are refused `unsupported`
// (PROTOCOL.md 9.12). One table: the rig loader reads the names, the image
// header writes the bits, the firmware core and the simulator gate on them.
#include <cstdint>

namespace nlsoft {

namespace feature {
constexpr uint32_t kIdent = 1u << 0;        // identification runs (IDENT_START)
constexpr uint32_t kModelUpload = 1u << 1;  // model uploads (XFER kind 2)
constexpr uint32_t kTableUpload = 1u << 2;  // reference-table uploads (XFER kind 1)
constexpr uint32_t kSettings = 1u << 3;     // saved settings (SETTINGS), on a board with a settings flash
// Not a name of the rig file: an image reads sensor chips when its rig has
// [[device]] tables, and only then.
constexpr uint32_t kChips = 1u << 8;
}  // namespace feature

struct FirmwareFeature {
  const char* name;  // in the rig file
  uint32_t bit;
  // INFO's capability bits of the service (protocol/messages.hpp
  // capability::, which firmware/core/firmware.hpp holds these equal to).
  uint32_t capabilities;
  const char* what;  // for messages: "built without <what>"
};

constexpr FirmwareFeature kFirmwareFeatures[] = {
    {"ident", feature::kIdent, (1u << 9) | (1u << 10), "identification runs (IDENT_START)"},
    {"model-upload", feature::kModelUpload, 1u << 3, "model uploads (XFER kind 2)"},
    {"table-upload", feature::kTableUpload, 1u << 2, "reference-table uploads (XFER kind 1)"},
    {"settings", feature::kSettings, 1u << 12, "saved settings (SETTINGS)"},
};

// The entry of a feature bit; null for none.
constexpr const FirmwareFeature* firmware_feature(uint32_t bit) {
  for (const FirmwareFeature& f : kFirmwareFeatures)
    if (f.bit == bit) return &f;
  return nullptr;
}

// What a rig file without [firmware] features asks for: every service the
// board can have (a board without a settings flash drops `settings`).
constexpr uint32_t kAllFirmwareFeatures =
    feature::kIdent | feature::kModelUpload | feature::kTableUpload | feature::kSettings;

}  // namespace nlsoft
