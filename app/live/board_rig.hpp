#pragma once
// The rig the firmware runs, as its rig file says (references, defaults):
// --sim/--qemu/--rig's file, else the shipped rig the firmware names; and
// whether the firmware's RIG_INFO matches the file given. Separate because
// parameters, references and scripts all ask it, and it is loaded once.
#include <atomic>
#include <mutex>
#include <optional>
#include <string>

#include "app/link/device.hpp"
#include "app/link/rig_hash.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

class BoardRig {
 public:
  // rig_file: empty for the shipped rig the firmware names.
  BoardRig(std::string rig_file, const Device& device) : rig_file_(std::move(rig_file)), device_(device) {}

  // Reads the rig file's identity: a file that cannot be read stops the
  // console before a simulator starts. Throws CliError.
  void open();
  // Any thread. Loaded on first use, then never replaced (references to it
  // stay valid). Throws CliError when the firmware runs a rig of its own
  // and no file was given.
  const Rig& rig() const;
  // The same, or nullptr where rig() would refuse: a firmware that runs a
  // rig of its own, no file given. A file that fails to load still throws.
  const Rig* known() const;
  // After each handshake: the firmware's RIG_INFO against the file given,
  // in words, once per console; "" when they agree, or said already.
  std::string mismatch();

 private:
  const std::string rig_file_;
  const Device& device_;
  std::optional<RigFileId> file_id_;
  std::atomic<bool> warned_{false};
  mutable std::mutex mu_;
  mutable std::optional<Rig> rig_;
};

}  // namespace nlsoft::console
