#pragma once
// CRC-32 (IEEE 802.3, reflected, poly 0xEDB88320): the model file trailer and
// content hash, table CRCs. Bitwise, no table: 1 KB of flash saved matters
// more here than speed (models are hashed once per upload).
#include <cstddef>
#include <cstdint>

namespace nlsoft {

inline uint32_t crc32_update(uint32_t crc, const uint8_t* data, size_t len) {
  crc = ~crc;
  for (size_t i = 0; i < len; ++i) {
    crc ^= data[i];
    for (int b = 0; b < 8; ++b) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

inline uint32_t crc32(const uint8_t* data, size_t len) { return crc32_update(0, data, len); }

}  // namespace nlsoft
