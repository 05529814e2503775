#include "app/link/rig_hash.hpp"

#include <fmt/format.h>

#include <sstream>

#include "app/input_file.hpp"
#include "app/printable.hpp"
#include "app/rig/rig_catalog.hpp"
#include "shared/crc32.hpp"

namespace nlsoft::console {

uint32_t rig_file_hash(const std::string& text) {
  // Hand-written: the canonical form is this protocol's definition
  // (PROTOCOL.md 7, RIG_INFO), not a TOML writer's, so that an image build
  // and any console compute it the same way without a TOML library.
  Crc32 crc;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::string kept;
    kept.reserve(line.size());
    for (char c : line)
      if (c != '\r') kept += c;
    while (!kept.empty() && (kept.back() == ' ' || kept.back() == '\t')) kept.pop_back();
    const size_t first = kept.find_first_not_of(" \t");
    if (first == std::string::npos || kept[first] == '#') continue;
    kept += '\n';
    crc.update(reinterpret_cast<const uint8_t*>(kept.data()), kept.size());
  }
  return crc.value();
}

RigFileId rig_file_id(const std::string& arg) {
  RigFileId id;
  id.path = rig_path(arg);
  id.name = load_rig_arg(arg).name;
  id.hash = rig_file_hash(read_input_file(id.path, InputKind{"rig file", 1u << 20}));
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
