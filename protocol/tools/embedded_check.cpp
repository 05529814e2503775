// Compiles every protocol header under the MCU rules (no exceptions, no RTTI,
// full warnings) on every build, and instantiates the templates a firmware
// uses, so a violation shows up in the host build long before a cross build.

#include "protocol/protocol.hpp"

namespace nlsoft::protocol {

size_t embedded_check_roundtrip(const uint8_t* in, size_t n, uint8_t* out, size_t cap) {
  Decoder decoder;
  DecodeResult result;
  size_t written = 0;
  size_t used = 0;
  while (used < n) {
    used += decoder.feed(in + used, n - used, result);
    if (result.kind != DecodeResult::Kind::Frame) continue;
    bool ok = with_message_type(result.frame.header.type, [&](auto msg) {
      if (unpack(result.frame, msg) != StatusCode::Ok) return;
      written += encode_reply(msg, result.frame.header.seq, out + written, cap - written);
    });
    (void)ok;
  }
  return written;
}

}  // namespace nlsoft::protocol
