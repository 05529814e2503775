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

#include "shared/crc32.hpp"

namespace nlsoft::protocol {

constexpr uint16_t kCrc16Init = 0xFFFF;

namespace detail {

struct Crc16Table {
  uint16_t entry[16];
};

constexpr Crc16Table make_crc16_table() {
  Crc16Table t{};
  for (unsigned i = 0; i < 16; ++i) {
    unsigned crc = i << 12;
    for (int bit = 0; bit < 4; ++bit) {
      crc = (crc & 0x8000u) ? ((crc << 1) ^ 0x1021u) : (crc << 1);
    }
    t.entry[i] = static_cast<uint16_t>(crc & 0xFFFFu);
  }
  return t;
}

// A nibble-wide table, as the CRC-32's: two lookups a byte from 32 bytes of
// flash, where a byte-wide one took 512 (a fiftieth of an MCU image's
// budget) for one lookup a byte.
inline constexpr Crc16Table kCrc16Table = make_crc16_table();

}  // namespace detail

constexpr uint16_t crc16_update(uint16_t crc, uint8_t byte) {
  unsigned c = crc;
  c = (c << 4) ^ detail::kCrc16Table.entry[((c >> 12) ^ (byte >> 4)) & 0x0Fu];
  c = (c << 4) ^ detail::kCrc16Table.entry[((c >> 12) ^ byte) & 0x0Fu];
  return static_cast<uint16_t>(c);
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

// CRC-32 for transfers: the one in shared/, which the model file uses too.
using nlsoft::Crc32;
using nlsoft::crc32;

}  // namespace nlsoft::protocol
