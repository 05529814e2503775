#pragma once
// Frame encoder into a caller-owned buffer. One pass: header, payload and
// CRC go through the CRC and the COBS writer together, so no intermediate
// raw frame is built beyond the packed payload.

#include <cstddef>
#include <cstdint>

#include "protocol/catalog.hpp"
#include "protocol/cobs.hpp"
#include "protocol/crc.hpp"
#include "protocol/frame.hpp"
#include "protocol/messages.hpp"
#include "protocol/status.hpp"

namespace nlsoft::protocol {

// Lowest level: every header byte and the CRC seed are explicit, so tools and
// tests can build frames a normal sender never would (wrong version, unknown
// type). Writes COBS image + delimiter; returns bytes written, 0 when the
// payload exceeds kMaxPayload or out_capacity is too small.
inline size_t encode_frame_raw(const Header& header, const uint8_t* payload, size_t length,
                               uint8_t crc_seed, uint8_t* out, size_t out_capacity) {
  if (length > kMaxPayload) return 0;
  const size_t raw = kHeaderSize + length + kCrcSize;
  if (out_capacity < cobs_max_encoded_size(raw) + 1) return 0;
  const uint8_t head[kHeaderSize] = {header.version, header.type, header.seq, header.flags,
                                     static_cast<uint8_t>(length)};
  CobsWriter w(out);
  uint16_t crc = crc16(head, kHeaderSize);
  w.put(head, kHeaderSize);
  crc = crc16(payload, length, crc);
  w.put(payload, length);
  crc = crc16_update(crc, crc_seed);
  w.put(static_cast<uint8_t>(crc & 0xFFu));
  w.put(static_cast<uint8_t>(crc >> 8));
  size_t n = w.finish();
  out[n++] = kDelimiter;
  return n;
}

// A frame of a catalogued type with a payload that obeys its length rule;
// returns 0 otherwise, so nothing the peer would reject leaves this side.
inline size_t encode_frame(uint8_t type, uint8_t seq, uint8_t flags, const uint8_t* payload,
                           size_t length, uint8_t* out, size_t out_capacity) {
  const MsgRule* rule = find_rule(type);
  if (rule == nullptr || !payload_length_ok(*rule, payload, length)) return 0;
  Header h;
  h.type = type;
  h.seq = seq;
  h.flags = flags;
  return encode_frame_raw(h, payload, length, rule->crc_extra, out, out_capacity);
}

// Typed: packs msg and frames it. Returns wire bytes written or 0.
template <class M>
size_t encode(const M& msg, uint8_t seq, uint8_t flags, uint8_t* out, size_t out_capacity) {
  uint8_t payload[kMaxPayload];
  // Empty messages never write the buffer; one store keeps GCC's
  // -Wmaybe-uninitialized quiet without zeroing 246 bytes per frame.
  payload[0] = 0;
  size_t length = 0;
  if (pack(msg, payload, sizeof payload, length) != StatusCode::Ok) return 0;
  return encode_frame(static_cast<uint8_t>(M::kType), seq, flags, payload, length, out,
                      out_capacity);
}

// The reply to a request: same seq, REPLY flag set.
template <class M>
size_t encode_reply(const M& msg, uint8_t request_seq, uint8_t* out, size_t out_capacity) {
  return encode(msg, request_seq, frame_flags::kReply, out, out_capacity);
}

}  // namespace nlsoft::protocol
