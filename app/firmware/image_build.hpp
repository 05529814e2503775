#pragma once
// Building a rig's Cortex-M images: its header generated (image_header.hpp),
// then the board's port project (firmware/ports/<board>) configured and
// built with arm-none-eabi-g++ over the firmware sources of the build tree
// or the install prefix (find_firmware_src). Into a folder of the user's
// (--out), or a cache folder keyed by the rig, the model and the board, so
// `--qemu FILE`, `conformance --qemu FILE` and `flash --rig FILE` find the
// image `firmware build` made, and build it when it is not there.
#include <string>

#include "host/rig/rig.hpp"

namespace nlsoft::console {

// How to build a rig's images; the rig itself is loaded by the caller, once.
struct ImageBuild {
  std::string board;  // a board of the board table (host/rig/board_table.hpp)
  std::string model;  // embedded; empty: the rig's [model] file among the shipped models, if found
  std::string out;    // where the images go; empty: the cache folder
  bool hil_only = false;
  std::string who = "firmware build";  // starts the error messages
};

struct BuiltImage {
  std::string path;
  long flash = 0, ram = 0;  // bytes: text + data, data + bss
};

struct BuiltImages {
  std::string dir;
  BuiltImage board, hil;  // path empty when not built
};

// Throws CliError: a bad rig, a board the rig does not fit, a missing
// toolchain (naming the Debian packages), a failed build (naming its log).
BuiltImages build_images(const host::Rig& rig, const ImageBuild& request);

// The image with the simulated plant for `rig` on `board`: $NLSOFT_M4_IMAGE;
// a shipped rig's built image when the rig is a shipped name or file as
// shipped; otherwise built (or found built) in the cache folder, embedding
// `model`, else the model of the image `firmware build --rig FILE --model M`
// made last from this very file (M unchanged since), else the rig's
// [model] file among the shipped models, else none.
std::string hil_image_for(const host::Rig& rig, const std::string& board, const std::string& who,
                          const std::string& model = "");

// The image (the board's, or the HIL one) for `rig` on `board`, the same
// way (the model of the one last built from the file, else the rig's).
std::string image_for(const host::Rig& rig, const std::string& board, bool hil, const std::string& who);

}  // namespace nlsoft::console
