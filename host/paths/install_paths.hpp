#pragma once
// Where the console's companion files are: nlsoft-firmware-sim, the
// Cortex-M images and the shipped models. Each is looked up relative to the
// running binary (/proc/self/exe), never through a path compiled in, so the
// build tree, an install prefix and a prefix moved elsewhere all work; an
// environment variable, when set, comes first.
//
//                    build tree                        install prefix
//   nlsoft-console   <build>/app/                      bin/
//   simulator        <build>/firmware/                 libexec/nlsoft/
//   images           <build>/firmware/{m4,m7,stm32f4}/ share/nlsoft/firmware/{m4,m7,stm32f4}/
//   models           <build>/share/nlsoft/models/      share/nlsoft/models/
//   rig files        <build>/share/nlsoft/rigs/        share/nlsoft/rigs/
//   firmware sources <build>/share/nlsoft/firmware-src share/nlsoft/firmware-src/
//                    (a link to the source tree)
#include <string>
#include <vector>

namespace nlsoft::host {

// The folder of the running executable; empty when /proc does not say.
std::string exe_dir();

// What a lookup found, or, when nothing, every place it looked, in order,
// so the error can name them all.
struct Lookup {
  std::string found;
  std::vector<std::string> tried;
  // "\n  <place>" per place tried.
  std::string tried_lines() const;
};

// nlsoft-firmware-sim: $NLSOFT_FIRMWARE_SIM, the build tree, beside the
// console, the install prefix's libexec/nlsoft/, then PATH.
Lookup find_firmware_sim_file();

// A Cortex-M image, `rel` as in "m4/nlsoft-m4-hasel-hil.elf": the build
// tree's firmware/<rel>, then the install prefix's share/nlsoft/firmware/<rel>.
Lookup find_image_file(const std::string& rel);

// A shipped model, `name` as in "hasel.nlsm": in $NLSOFT_MODELS, then the
// build tree's and the install prefix's share/nlsoft/models/.
Lookup find_model_file(const std::string& name);

// The shipped rig files' folder: $NLSOFT_RIGS, then the build tree's and the
// install prefix's share/nlsoft/rigs/.
Lookup find_rigs_dir();

// The folders a rig is looked up in by name, in order: $NLSOFT_RIGS (when
// it is a folder) first, then the shipped rigs' (the build tree's, else the
// install prefix's). A name missing from the first is found in the second.
struct RigsFolder {
  std::string dir;
  bool from_env = false;  // $NLSOFT_RIGS
};
std::vector<RigsFolder> rigs_folders();

// The sources an image is built from (firmware/, shared/, protocol/,
// cmake/warning_flags.txt): $NLSOFT_FIRMWARE_SRC, then the build tree's and
// the install prefix's share/nlsoft/firmware-src.
Lookup find_firmware_src();

// `name` in a folder of $PATH, or empty.
std::string find_on_path(const std::string& name);

}  // namespace nlsoft::host
