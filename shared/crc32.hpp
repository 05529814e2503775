#pragma once
// CRC-32 (IEEE 802.3 / zlib: reflected poly 0xEDB88320, init and final XOR
// 0xFFFFFFFF; check value of "123456789" = 0xCBF43926): the model file's
// trailer and content hash, and the protocol's transfer checksum. One
// implementation for both.
//
// Nibble-wide table: CRC-32 runs once per model or transferred object, not
// per frame, so 64 bytes of flash beat the 1 KiB byte-wide table.
// Incremental, so the firmware can checksum a transfer chunk by chunk as it
// arrives instead of re-reading the whole object at commit.
#include <cstddef>
#include <cstdint>

namespace nlsoft {

namespace detail {
inline constexpr uint32_t kCrc32Nibble[16] = {
    0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u,
    0x4DB26158u, 0x5005713Cu, 0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu,
    0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu};
}  // namespace detail

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

}  // namespace nlsoft
