#pragma once
// The protocol revision this console speaks, as protocol/PROTOCOL.md names
// it ("1.2"): the frame's version byte and INFO_EX's protocol_minor, put
// together in this one place for every message that names it.
#include <string>

#include "protocol/frame.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::console {

inline std::string protocol_version_text() {
  return std::to_string(protocol::kProtocolVersion) + "." + std::to_string(protocol::kProtocolMinor);
}

}  // namespace nlsoft::console
