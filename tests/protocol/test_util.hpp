#pragma once
// Small helpers shared by the protocol tests.

#include <cstdint>
#include <vector>

#include "protocol/cobs.hpp"
#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"

namespace nlsoft::protocol::test {

using Bytes = std::vector<uint8_t>;

template <class M>
Bytes wire_of(const M& msg, uint8_t seq = 1, uint8_t flags = 0) {
  uint8_t buf[kWireBufferSize];
  const size_t n = encode(msg, seq, flags, buf, sizeof buf);
  return Bytes(buf, buf + n);
}

// COBS + delimiter around an arbitrary raw frame, for hand-made bad frames.
inline Bytes wire_of_raw(const Bytes& raw) {
  Bytes out(cobs_max_encoded_size(raw.size()) + 1);
  out.resize(cobs_encode(raw.data(), raw.size(), out.data(), out.size()));
  out.push_back(0);
  return out;
}

// Raw frame with a correct CRC for the given seed type.
inline Bytes raw_frame(uint8_t version, uint8_t type, uint8_t seq, const Bytes& payload,
                       uint8_t seed_type) {
  Bytes raw = {version, type, seq, 0, static_cast<uint8_t>(payload.size())};
  raw.insert(raw.end(), payload.begin(), payload.end());
  uint16_t crc = crc16(raw.data(), raw.size());
  crc = crc16_update(crc, crc_extra(seed_type));
  raw.push_back(static_cast<uint8_t>(crc & 0xFF));
  raw.push_back(static_cast<uint8_t>(crc >> 8));
  return raw;
}

struct Event {
  DecodeResult::Kind kind;
  FrameError error;
  Header header;
  Bytes payload;
};

inline std::vector<Event> decode_all(Decoder& d, const Bytes& wire, size_t chunk = 0) {
  std::vector<Event> events;
  size_t pos = 0;
  while (pos < wire.size()) {
    size_t avail = wire.size() - pos;
    if (chunk != 0 && avail > chunk) avail = chunk;
    DecodeResult r;
    pos += d.feed(wire.data() + pos, avail, r);
    if (r.kind == DecodeResult::Kind::None) continue;
    Event e{r.kind, r.error, r.frame.header, {}};
    if (r.kind == DecodeResult::Kind::Frame) {
      e.payload.assign(r.frame.payload, r.frame.payload + r.frame.payload_size());
    }
    events.push_back(e);
  }
  return events;
}

inline std::vector<Event> decode_all(const Bytes& wire, size_t chunk = 0) {
  Decoder d;
  return decode_all(d, wire, chunk);
}

}  // namespace nlsoft::protocol::test
