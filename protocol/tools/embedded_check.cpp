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

namespace nlsoft::protocol {

// The firmware-side helpers, instantiated under the same rules.
size_t embedded_check_transfer(const XferBegin& b, const XferChunk& c, uint8_t* stage,
                               size_t cap, uint8_t* out, size_t out_cap) {
  TransferReceiver rx(static_cast<uint8_t>(XferKind::RefTable), stage, cap);
  ReplyCache cache;
  FrameView h;
  h.header.type = static_cast<uint8_t>(MsgType::XferChunk);
  const uint8_t* wire = nullptr;
  size_t n = 0;
  if (cache.find(h, wire, n)) return n;
  rx.begin(b);
  const XferReply r = rx.chunk(c);
  n = encode_reply(r.ack, h.header.seq, out, out_cap);
  cache.store(h, out, n);
  return rx.commit().status == StatusCode::Ok ? n : 0;
}

}  // namespace nlsoft::protocol

#include "shared/capacity.hpp"

namespace nlsoft::protocol {

// An image's capacity as the generator writes one: a hasel-sized rig with
// one Dense 5-5-3 shape.
struct EmbeddedCheckCapacity {
  static constexpr int m = 6, n = 3, w = 18, nd = 2;
  static constexpr int N = 4, Nc = 1;
  static constexpr int width = ShapeNeeds<HaselShape>::width, layers = 4, weights = ShapeNeeds<HaselShape>::weights;
  using Shapes = ShapeList<HaselShape>;
  static constexpr bool generic = false;
};

// RIG_INFO's shapes from an MCU capacity and the verdict on a model header.
bool embedded_check_shapes(const uint8_t* header, size_t len, uint8_t* out, size_t out_cap) {
  RigInfo r;
  r.m = 6, r.n = 3, r.w = 18, r.nd = r.dd = 2;
  if (!fill_accepted_shapes<EmbeddedCheckCapacity>(r)) return false;
  ModelShape s;
  if (!model_shape(header, len, s)) return false;
  return accepts(r, s) == ShapeVerdict::Accepted && size_fits_a_shape(r, uint32_t(len)) &&
         encode_reply(r, 1, out, out_cap) != 0;
}

}  // namespace nlsoft::protocol
