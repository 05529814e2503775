#pragma once
// Checksums of the wire protocol (see PROTOCOL.md, "Checksums").
//
// CRC-16/CCITT-FALSE guards every frame: two bytes is enough for frames of at
// most 253 bytes (Hamming distance 4 up to 4095 bits) and it is what MAVLink
// uses, so peers in other languages find it in every CRC library.
// CRC-32 (IEEE 802.3, the zlib one) guards whole transferred objects, which
// can be far longer than a frame.

#include <cstddef>
#include <cstdint>

namespace nlsoft::protocol {

constexpr uint16_t kCrc16Init = 0xFFFF;

namespace detail {

struct Crc16Table {
  uint16_t entry[256];
};

constexpr Crc16Table make_crc16_table() {
  Crc16Table t{};
  for (unsigned i = 0; i < 256; ++i) {
    unsigned crc = i << 8;
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x8000u) ? ((crc << 1) ^ 0x1021u) : (crc << 1);
    }
    t.entry[i] = static_cast<uint16_t>(crc & 0xFFFFu);
  }
  return t;
}

// A byte-wide table: 512 bytes of flash buys a table lookup per byte instead
// of eight shifts, which is what keeps the decoder off the profile.
inline constexpr Crc16Table kCrc16Table = make_crc16_table();

// Nibble-wide table: CRC-32 runs once per transferred object, not per frame,
// so 64 bytes of flash beat the 1 KiB byte-wide table.
inline constexpr uint32_t kCrc32Nibble[16] = {
    0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u,
    0x4DB26158u, 0x5005713Cu, 0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu,
    0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu};

}  // namespace detail

constexpr uint16_t crc16_update(uint16_t crc, uint8_t byte) {
  return static_cast<uint16_t>(
      static_cast<unsigned>(crc << 8) ^
      detail::kCrc16Table.entry[static_cast<uint8_t>((crc >> 8) ^ byte)]);
}

constexpr uint16_t crc16(const uint8_t* data, size_t len, uint16_t crc = kCrc16Init) {
  for (size_t i = 0; i < len; ++i) crc = crc16_update(crc, data[i]);
  return crc;
}

// Over the characters of a NUL-terminated string; used at compile time to
// derive each message type's CRC seed from its layout signature.
constexpr uint16_t crc16_str(const char* s, uint16_t crc = kCrc16Init) {
  while (*s != '\0') crc = crc16_update(crc, static_cast<uint8_t>(*s++));
  return crc;
}

// Incremental, so the firmware can checksum a transfer chunk by chunk as it
// arrives instead of re-reading the whole object at commit.
class Crc32 {
 public:
  constexpr void update(const uint8_t* data, size_t len) {
    for (size_t i = 0; i < len; ++i) {
      state_ ^= data[i];
      state_ = (state_ >> 4) ^ detail::kCrc32Nibble[state_ & 0x0Fu];
      state_ = (state_ >> 4) ^ detail::kCrc32Nibble[state_ & 0x0Fu];
    }
  }
  constexpr uint32_t value() const { return state_ ^ 0xFFFFFFFFu; }
  constexpr void reset() { state_ = 0xFFFFFFFFu; }

 private:
  uint32_t state_ = 0xFFFFFFFFu;
};

constexpr uint32_t crc32(const uint8_t* data, size_t len) {
  Crc32 c;
  c.update(data, len);
  return c.value();
}

}  // namespace nlsoft::protocol
