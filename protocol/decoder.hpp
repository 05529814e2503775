#pragma once
// Incremental frame decoder: feed it whatever the UART or USB stack hands
// over (one byte from an ISR or a 64-byte USB packet), get back one event per
// frame: a validated frame or the reason it was dropped.
//
// COBS is undone on the fly into a kMaxRawFrame buffer, so the decoder holds
// one frame, never the encoded image, and validation runs once at the
// delimiter. Any garbage costs at most the frame it lands in: the next 0x00
// always restarts decoding.

#include <cstddef>
#include <cstdint>

#include "protocol/catalog.hpp"
#include "protocol/crc.hpp"
#include "protocol/frame.hpp"
#include "protocol/status.hpp"

namespace nlsoft::protocol {

struct DecodeResult {
  enum class Kind : uint8_t { None, Frame, Error };

  Kind kind = Kind::None;
  FrameError error = FrameError::None;
  // For Frame: the validated frame. For Error: whatever header bytes arrived
  // (zero otherwise), untrusted, for diagnostics only.
  FrameView frame;
};

struct DecoderStats {
  uint32_t bytes = 0;
  uint32_t frames_ok = 0;
  // Back-to-back delimiters; harmless (senders may flush with a 0x00).
  uint32_t empty_frames = 0;
  uint32_t errors[kFrameErrorCount] = {};

  uint32_t error_count(FrameError e) const { return errors[static_cast<unsigned>(e)]; }
  uint32_t error_total() const {
    uint32_t total = 0;
    for (unsigned i = 1; i < kFrameErrorCount; ++i) total += errors[i];
    return total;
  }
};

class Decoder {
 public:
  // Consumes bytes up to and including the delimiter that completes a frame
  // (then result.kind is Frame or Error) or all of them (kind None).
  // Returns the number consumed; call again with the rest.
  size_t feed(const uint8_t* data, size_t len, DecodeResult& result) {
    result = DecodeResult{};
    size_t i = 0;
    while (i < len) {
      if (remaining_ > 1 && !overflow_) i += copy_run(data + i, len - i);
      if (i == len) break;
      if (step(data[i++], result)) {
        stats_.bytes += static_cast<uint32_t>(i);
        return i;
      }
    }
    stats_.bytes += static_cast<uint32_t>(len);
    return len;
  }

  DecodeResult push(uint8_t byte) {
    DecodeResult result;
    step(byte, result);
    ++stats_.bytes;
    return result;
  }

  // Drops any partial frame, e.g. after the port was reopened.
  void reset() { restart(); }

  const DecoderStats& stats() const { return stats_; }
  void clear_stats() { stats_ = DecoderStats{}; }

 private:
  bool step(uint8_t b, DecodeResult& result) {
    if (b == kDelimiter) return finish(result);
    if (overflow_) return false;
    if (remaining_ == 0) {
      // Code byte. The zero it implies belongs to the end of the previous
      // block, so it is only written once we know another block follows;
      // that is what drops the phantom zero at the end of the frame.
      if (code_ != 0 && code_ != 0xFF) append(0);
      code_ = b;
      remaining_ = static_cast<uint8_t>(b - 1);
    } else {
      append(b);
      --remaining_;
    }
    return false;
  }

  // Inside a COBS block every byte but the block's last is plain data: copy
  // it without the per-byte state machine. Stops one short of the block end,
  // at a delimiter or at buffer capacity, leaving those cases to step().
  size_t copy_run(const uint8_t* data, size_t avail) {
    size_t n = static_cast<size_t>(remaining_ - 1);
    if (n > avail) n = avail;
    if (n > kMaxRawFrame - len_) n = kMaxRawFrame - len_;
    size_t k = 0;
    while (k < n && data[k] != kDelimiter) {
      buf_[len_ + k] = data[k];
      ++k;
    }
    len_ += k;
    remaining_ = static_cast<uint8_t>(remaining_ - k);
    return k;
  }

  void append(uint8_t b) {
    if (len_ == kMaxRawFrame) {
      overflow_ = true;
      return;
    }
    buf_[len_++] = b;
  }

  bool finish(DecodeResult& result) {
    if (!overflow_ && code_ == 0) {
      ++stats_.empty_frames;
      return false;
    }
    FrameError error = FrameError::None;
    if (overflow_) {
      error = FrameError::Oversize;
    } else if (remaining_ != 0) {
      error = FrameError::CobsError;
    } else {
      error = validate(result.frame);
    }
    if (error == FrameError::None) {
      result.kind = DecodeResult::Kind::Frame;
      ++stats_.frames_ok;
    } else {
      result.kind = DecodeResult::Kind::Error;
      result.error = error;
      ++stats_.errors[static_cast<unsigned>(error)];
      if (error != FrameError::Oversize) fill_header(result.frame.header);
    }
    restart();
    return true;
  }

  FrameError validate(FrameView& view) const {
    // Order matters: PROTOCOL.md fixes it so every peer reports the same
    // reason. The version comes first because a later revision may change
    // everything after byte 0.
    if (len_ == 0) return FrameError::Truncated;
    if (buf_[header_offset::kVersion] != kProtocolVersion) return FrameError::WrongVersion;
    if (len_ < kHeaderSize + kCrcSize) return FrameError::Truncated;
    const size_t payload_len = buf_[header_offset::kLength];
    const size_t expected = kHeaderSize + payload_len + kCrcSize;
    if (len_ < expected) return FrameError::Truncated;
    if (len_ > expected) return FrameError::LengthMismatch;
    const uint8_t type = buf_[header_offset::kType];
    const MsgRule* rule = find_rule(type);
    if (rule == nullptr) return FrameError::UnknownType;
    uint16_t crc = crc16(buf_, kHeaderSize + payload_len);
    crc = crc16_update(crc, rule->crc_extra);
    const size_t c = kHeaderSize + payload_len;
    const auto wire_crc = static_cast<uint16_t>(buf_[c] | (buf_[c + 1] << 8));
    if (crc != wire_crc) return FrameError::BadCrc;
    if (!payload_length_ok(*rule, buf_ + kHeaderSize, payload_len)) return FrameError::BadLength;
    fill_header(view.header);
    view.payload = buf_ + kHeaderSize;
    return FrameError::None;
  }

  void fill_header(Header& h) const {
    h = Header{};
    h.version = len_ > 0 ? buf_[0] : 0;
    if (len_ >= kHeaderSize) {
      h.type = buf_[header_offset::kType];
      h.seq = buf_[header_offset::kSeq];
      h.flags = buf_[header_offset::kFlags];
      h.length = buf_[header_offset::kLength];
    }
  }

  void restart() {
    len_ = 0;
    remaining_ = 0;
    code_ = 0;
    overflow_ = false;
  }

  uint8_t buf_[kMaxRawFrame] = {};
  size_t len_ = 0;
  uint8_t remaining_ = 0;  // data bytes still due in the current COBS block
  uint8_t code_ = 0;       // current block's code byte; 0 before the first
  bool overflow_ = false;
  DecoderStats stats_;
};

}  // namespace nlsoft::protocol
