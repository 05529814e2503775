#include "app/link/rig_hash.hpp"

#include <fmt/format.h>

#include "host/files/printable.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

using host::Rig;
using host::printable;

RigFileId rig_file_id(const Rig& rig) {
  RigFileId id;
  id.path = rig.file;
  id.name = rig.name;
  id.hash = rig.hash;
  return id;
}

std::string rig_mismatch(const protocol::RigInfo& rig, const RigFileId& file) {
  const std::string name = printable(rig.rig_name);
  if (name != file.name)
    return fmt::format("warning: the firmware runs rig {} (hash {:08x}), not {}'s rig {} (hash {:08x}): it was built "
                       "from another rig file",
                       name.empty() ? "(unnamed)" : name, rig.rig_hash, file.path, file.name, file.hash);
  if (rig.rig_hash == 0 || rig.rig_hash == file.hash) return "";
  return fmt::format("warning: the firmware's rig {} has hash {:08x}, {} has {:08x}: the image was built from "
                     "another version of the rig file",
                     name, rig.rig_hash, file.path, file.hash);
}

}  // namespace nlsoft::console
