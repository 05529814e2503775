#pragma once
// Consistent Overhead Byte Stuffing (Cheshire & Baker, 1999).
//
// COBS removes every 0x00 from a frame at a cost of one byte per 254, so 0x00
// can delimit frames: a receiver that lost sync only has to wait for the next
// 0x00, whatever garbage it saw. The streaming decoder lives in decoder.hpp;
// these are the whole-buffer forms plus the streaming writer the encoder uses.

#include <cstddef>
#include <cstdint>

namespace nlsoft::protocol {

constexpr size_t cobs_max_encoded_size(size_t n) { return n + n / 254 + 1; }

// Streams bytes into COBS form. The caller guarantees capacity up front
// (cobs_max_encoded_size), which keeps bounds checks out of the per-byte path.
class CobsWriter {
 public:
  explicit CobsWriter(uint8_t* out) : out_(out) {}

  void put(uint8_t b) {
    // A full block is closed lazily, only when another byte needs a fresh one,
    // so 254 non-zero bytes at the end do not cost a redundant 0x01 code.
    if (code_ == 0xFF) close_block();
    if (b == 0) {
      close_block();
    } else {
      out_[pos_++] = b;
      ++code_;
    }
  }
  void put(const uint8_t* data, size_t n) {
    for (size_t i = 0; i < n; ++i) put(data[i]);
  }
  // Returns the encoded size (without any delimiter).
  size_t finish() {
    out_[code_pos_] = code_;
    return pos_;
  }

 private:
  void close_block() {
    out_[code_pos_] = code_;
    code_pos_ = pos_++;
    code_ = 1;
  }

  uint8_t* out_;
  size_t code_pos_ = 0;
  size_t pos_ = 1;
  uint8_t code_ = 1;
};

// Encodes n bytes (no delimiter written). Returns the encoded size, or 0 when
// out_capacity < cobs_max_encoded_size(n).
inline size_t cobs_encode(const uint8_t* in, size_t n, uint8_t* out, size_t out_capacity) {
  if (out_capacity < cobs_max_encoded_size(n)) return 0;
  CobsWriter w(out);
  w.put(in, n);
  return w.finish();
}

struct CobsDecodeResult {
  bool ok;
  size_t size;
};

// Decodes one COBS block sequence without its delimiter. Fails on a 0x00
// inside the input, on a block that runs past the end, or on lack of room.
inline CobsDecodeResult cobs_decode(const uint8_t* in, size_t n, uint8_t* out,
                                    size_t out_capacity) {
  size_t o = 0;
  size_t i = 0;
  while (i < n) {
    const uint8_t code = in[i++];
    if (code == 0) return {false, o};
    const size_t run = static_cast<size_t>(code) - 1;
    if (n - i < run || out_capacity - o < run) return {false, o};
    for (size_t k = 0; k < run; ++k) {
      if (in[i] == 0) return {false, o};
      out[o++] = in[i++];
    }
    if (code != 0xFF && i < n) {
      if (o == out_capacity) return {false, o};
      out[o++] = 0;
    }
  }
  return {true, o};
}

}  // namespace nlsoft::protocol
