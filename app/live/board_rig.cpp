// A rig named by the firmware's platform number is read from the shipped
// rig files; a rig of the firmware's own needs its file.
#include "app/live/board_rig.hpp"

#include "host/files/cli_error.hpp"
#include "host/rig/rig_catalog.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::load_rig_arg;
using host::rig_name_of_platform;

BoardRig::BoardRig(std::shared_ptr<const Rig> given, const Device& device)
    : given_(std::move(given)), device_(device) {
  if (given_) file_id_ = rig_file_id(*given_);
}

const Rig& BoardRig::rig() const {
  if (given_) return *given_;
  std::lock_guard<std::mutex> lock(mu_);
  if (shipped_) return *shipped_;
  const std::string shipped = rig_name_of_platform(device_.info().platform);
  if (shipped.empty())
    throw CliError("the firmware runs a rig of its own (no shipped rig's number); give its rig file: --rig FILE");
  shipped_ = load_rig_arg(shipped);
  return *shipped_;
}

const Rig* BoardRig::known() const {
  if (!given_ && rig_name_of_platform(device_.info().platform).empty()) return nullptr;
  return &rig();
}

std::string BoardRig::mismatch() {
  if (!file_id_ || warned_) return "";
  const std::optional<protocol::RigInfo> rig = device_.rig();
  if (!rig) return "";  // a 1.1 firmware names no rig
  const std::string w = rig_mismatch(*rig, *file_id_);
  if (w.empty() || warned_.exchange(true)) return "";
  return w;
}

}  // namespace nlsoft::console
