#pragma once
// The rig file the console was given as RIG_INFO names it (its rig_hash,
// PROTOCOL.md 7: Rig::hash, host/rig/rig_loader.cpp), and what the console says when the firmware names another rig
// than the file it was started with.
#include <cstdint>
#include <string>

#include "host/rig/rig.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::console {

// The rig file the console was given, as RIG_INFO would name it.
struct RigFileId {
  std::string path, name;
  uint32_t hash = 0;
};

// The loaded rig's file, name and hash.
RigFileId rig_file_id(const host::Rig& rig);

// Empty when the firmware's RIG_INFO matches the file, or names no hash
// (0: the image was not built from a rig file); else one warning line.
std::string rig_mismatch(const protocol::RigInfo& rig, const RigFileId& file);

}  // namespace nlsoft::console
