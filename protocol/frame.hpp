#pragma once
// Frame layout (PROTOCOL.md, "Framing" and "Header").
//
//   wire:  COBS( header | payload | crc16 LE ) 0x00
//   header: version, type, seq, flags, payload length  (5 bytes)
//
// Raw frames are capped at 253 bytes so that the COBS image is always exactly
// one byte longer (one code byte per 254 bytes) and a whole wire frame,
// delimiter included, fits a 256-byte MCU buffer with a byte to spare for a
// leading delimiter.

#include <cstddef>
#include <cstdint>

namespace nlsoft::protocol {

constexpr uint8_t kProtocolVersion = 1;

constexpr size_t kHeaderSize = 5;
constexpr size_t kCrcSize = 2;
constexpr size_t kMaxRawFrame = 253;
constexpr size_t kMaxPayload = kMaxRawFrame - kHeaderSize - kCrcSize;  // 246
constexpr size_t kMaxEncodedFrame = kMaxRawFrame + 1;                  // 254
constexpr size_t kMaxWireFrame = kMaxEncodedFrame + 1;                 // 255, with delimiter
// What a caller should allocate for one outgoing wire frame.
constexpr size_t kWireBufferSize = 256;

constexpr uint8_t kDelimiter = 0x00;

namespace header_offset {
constexpr size_t kVersion = 0;
constexpr size_t kType = 1;
constexpr size_t kSeq = 2;
constexpr size_t kFlags = 3;
constexpr size_t kLength = 4;
}  // namespace header_offset

namespace frame_flags {
// Set on the one reply to a request; the reply echoes the request's seq.
// Clear on requests and on unsolicited frames (TELEMETRY, STATUS, LOG).
constexpr uint8_t kReply = 0x01;
// Bits 1..7 are reserved: senders write 0, receivers ignore them, so a later
// revision can use them without breaking older peers.
}  // namespace frame_flags

struct Header {
  uint8_t version = kProtocolVersion;
  uint8_t type = 0;
  uint8_t seq = 0;
  uint8_t flags = 0;
  uint8_t length = 0;  // payload bytes
};

// A decoded, validated frame. payload points into the decoder's buffer and is
// valid until the decoder is fed again.
struct FrameView {
  Header header;
  const uint8_t* payload = nullptr;

  size_t payload_size() const { return header.length; }
  bool is_reply() const { return (header.flags & frame_flags::kReply) != 0; }
};

}  // namespace nlsoft::protocol
