#pragma once
// The rig the firmware runs, as its rig file says (references, defaults):
// --sim/--qemu/--rig's rig (loaded by live_options), else the shipped rig
// the firmware names; and whether the firmware's RIG_INFO matches the file
// given. Separate because parameters, references and scripts all ask it.
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "app/link/device.hpp"
#include "app/link/rig_hash.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

class BoardRig {
 public:
  // given: nullptr for the shipped rig the firmware names.
  BoardRig(std::shared_ptr<const host::Rig> given, const Device& device);

  // Any thread. The rig given, else the shipped one loaded on first use;
  // never replaced (references to it stay valid). Throws CliError when the
  // firmware runs a rig of its own and no file was given.
  const host::Rig& rig() const;
  // The same, or nullptr where rig() would refuse: a firmware that runs a
  // rig of its own, no file given. A file that fails to load still throws.
  const host::Rig* known() const;
  // After each handshake: the firmware's RIG_INFO against the file given,
  // in words, once per console; "" when they agree, or said already.
  std::string mismatch();

 private:
  const std::shared_ptr<const host::Rig> given_;
  const Device& device_;
  std::optional<RigFileId> file_id_;
  std::atomic<bool> warned_{false};
  mutable std::mutex mu_;
  mutable std::optional<host::Rig> shipped_;
};

}  // namespace nlsoft::console
