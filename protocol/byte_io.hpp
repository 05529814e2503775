#pragma once
// Little-endian field access over caller-owned buffers. Both classes latch a
// failure instead of returning one per call, so a message's pack/unpack can
// be written as a flat list of fields and checked once at the end.

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace nlsoft::protocol {

class ByteWriter {
 public:
  ByteWriter(uint8_t* buf, size_t capacity) : buf_(buf), cap_(capacity) {}

  void u8(uint8_t v) {
    if (!room(1)) return;
    buf_[pos_++] = v;
  }
  void u16(uint16_t v) {
    if (!room(2)) return;
    buf_[pos_++] = static_cast<uint8_t>(v);
    buf_[pos_++] = static_cast<uint8_t>(v >> 8);
  }
  void u32(uint32_t v) {
    if (!room(4)) return;
    buf_[pos_++] = static_cast<uint8_t>(v);
    buf_[pos_++] = static_cast<uint8_t>(v >> 8);
    buf_[pos_++] = static_cast<uint8_t>(v >> 16);
    buf_[pos_++] = static_cast<uint8_t>(v >> 24);
  }
  // IEEE-754 binary32 bit pattern, little-endian; memcpy is the only
  // well-defined way to get at the bits and compiles to a register move.
  void f32(float v) {
    uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    u32(bits);
  }
  void bytes(const void* src, size_t n) {
    if (!room(n)) return;
    if (n != 0) std::memcpy(buf_ + pos_, src, n);
    pos_ += n;
  }
  void fail() { ok_ = false; }

  bool ok() const { return ok_; }
  size_t size() const { return pos_; }

 private:
  bool room(size_t n) {
    if (!ok_ || cap_ - pos_ < n) {
      ok_ = false;
      return false;
    }
    return true;
  }

  uint8_t* buf_;
  size_t cap_;
  size_t pos_ = 0;
  bool ok_ = true;
};

class ByteReader {
 public:
  ByteReader(const uint8_t* buf, size_t size) : buf_(buf), size_(size) {}

  uint8_t u8() {
    if (!have(1)) return 0;
    return buf_[pos_++];
  }
  uint16_t u16() {
    if (!have(2)) return 0;
    const auto v = static_cast<uint16_t>(buf_[pos_] | (buf_[pos_ + 1] << 8));
    pos_ += 2;
    return v;
  }
  uint32_t u32() {
    if (!have(4)) return 0;
    const uint32_t v = static_cast<uint32_t>(buf_[pos_]) |
                       (static_cast<uint32_t>(buf_[pos_ + 1]) << 8) |
                       (static_cast<uint32_t>(buf_[pos_ + 2]) << 16) |
                       (static_cast<uint32_t>(buf_[pos_ + 3]) << 24);
    pos_ += 4;
    return v;
  }
  float f32() {
    const uint32_t bits = u32();
    float v = 0.0f;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  void bytes(void* dst, size_t n) {
    if (!have(n)) return;
    if (n != 0) std::memcpy(dst, buf_ + pos_, n);
    pos_ += n;
  }
  void skip(size_t n) {
    if (have(n)) pos_ += n;
  }
  void fail() { ok_ = false; }

  bool ok() const { return ok_; }
  size_t remaining() const { return size_ - pos_; }

 private:
  bool have(size_t n) {
    if (!ok_ || size_ - pos_ < n) {
      ok_ = false;
      return false;
    }
    return true;
  }

  const uint8_t* buf_;
  size_t size_;
  size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace nlsoft::protocol
