// libFuzzer target for rig files, the one text a user writes that every
// part of the product reads (docs/rig-file.md): parse_rig must accept a
// file or refuse it with a RigError naming a line of it, never crash,
// hang or throw anything else; an accepted file must give the firmware's
// view (firmware_rig), its reference and, with a generic [plant], a plant
// spec the plant's own check passes. Built with clang under ASan+UBSan
// (NLSOFT_FUZZ=ON); CI runs it briefly in `cmake/dev sanitize`, seeded with
// the shipped rig files:
//   host/rig/fuzz/run_fuzz.sh build-fuzz 60
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "host/rig/firmware_rig.hpp"
#include "host/rig/rig.hpp"
#include "host/rig/rig_plant.hpp"

namespace r = nlsoft::host;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  r::Rig rig;
  try {
    rig = r::parse_rig(text, "fuzz.toml");
  } catch (const r::RigError& e) {
    // A refusal names a line of the file (0: the file as a whole) and never
    // one past its end.
    size_t lines = 1;
    for (char c : text) lines += c == '\n';
    if (e.line < 0 || size_t(e.line) > lines) {
      std::fprintf(stderr, "refusal at line %d of a %zu-line file: %s\n", e.line, lines, e.what());
      std::abort();
    }
    return 0;
  }
  const nlsoft::RigConfig c = r::firmware_rig(rig);
  if (c.m != rig.m() || c.n != rig.n() || c.w != rig.w() || c.features != rig.firmware_features) std::abort();
  if (r::has_generic_plant(rig)) {
    if (const char* problem = nlsoft::generic_spec_problem(r::generic_plant_spec(rig))) {
      std::fprintf(stderr, "an accepted generic plant its own check refuses: %s\n", problem);
      std::abort();
    }
  }
  return 0;
}
