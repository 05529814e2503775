#pragma once
// RIG_INFO's rig_hash (PROTOCOL.md 7): the CRC-32 of a rig file's canonical
// content, and what the console says when the firmware names another rig
// than the file it was started with.
#include <cstdint>
#include <string>

#include "protocol/messages.hpp"

namespace nlsoft::console {

// CRC-32 of `text` without CRs, trailing blanks, and lines that are then
// empty or comments: layout and comment lines do not change a rig.
uint32_t rig_file_hash(const std::string& text);

// The rig file the console was given, as RIG_INFO would name it.
struct RigFileId {
  std::string path, name;
  uint32_t hash = 0;
};

// Reads and hashes the rig file `arg` names (a shipped name or a path).
// Throws CliError as the rig commands do.
RigFileId rig_file_id(const std::string& arg);

// Empty when the firmware's RIG_INFO matches the file, or names no hash
// (0: the image was not built from a rig file); else one warning line.
std::string rig_mismatch(const protocol::RigInfo& rig, const RigFileId& file);

}  // namespace nlsoft::console
