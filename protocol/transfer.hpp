#pragma once
// Receiving side of the chunked transfer (PROTOCOL.md, section 9.4), one
// instance per transfer kind, over a caller-owned staging buffer. It owns the
// offset and CRC rules so every firmware port answers BEGIN/CHUNK/COMMIT the
// same way; validating the object and swapping it in stay with the caller,
// who keeps the object in force in a separate buffer until commit succeeds.

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "protocol/crc.hpp"
#include "protocol/messages.hpp"
#include "protocol/status.hpp"

namespace nlsoft::protocol {

// What to send back: XFER_ACK (`ack`) when status is Ok, otherwise a NACK
// with status and field (element is always 255 for transfers).
struct XferReply {
  StatusCode status = StatusCode::Ok;
  uint8_t field = kNoField;
  XferAck ack;
};

class TransferReceiver {
 public:
  TransferReceiver(uint8_t kind, uint8_t* buffer, size_t capacity)
      : kind_(kind), buf_(buffer), cap_(capacity) {}

  // The largest total_size BEGIN accepts (INFO_EX advertises it).
  size_t capacity() const { return cap_; }

  XferReply begin(const XferBegin& m) {
    if (m.total_size == 0) return nack(StatusCode::OutOfRange, 2);
    if (m.total_size > cap_) return nack(StatusCode::TooLarge, 2);
    const bool same = open_ && m.total_size == total_ && m.crc32 == crc_expected_;
    if (!same || (m.options & xfer_options::kRestart) != 0) {
      open_ = true;
      total_ = m.total_size;
      crc_expected_ = m.crc32;
      next_ = 0;
      crc_.reset();
    }
    return ack();
  }

  XferReply chunk(const XferChunk& m) {
    if (!open_) return nack(StatusCode::XferNotOpen, 0);
    if (m.offset > total_ || m.size > total_ - m.offset) return nack(StatusCode::OutOfRange, 1);
    // Only the chunk that continues the object is stored; duplicates and
    // chunks after a gap are dropped and the ack says where to continue.
    if (m.offset == next_ && m.size > 0) {
      std::memcpy(buf_ + next_, m.data, m.size);
      crc_.update(m.data, m.size);
      next_ += m.size;
    }
    return ack();
  }

  // Completeness and CRC. Ok means the staged object is intact: validate
  // data()/size(), swap it in, then call close(). A CRC failure discards the
  // transfer; an incomplete one stays open for resuming.
  XferReply commit() {
    if (!open_) return nack(StatusCode::XferNotOpen, 0);
    if (next_ < total_) return nack(StatusCode::XferIncomplete, kNoField);
    if (crc_.value() != crc_expected_) {
      close();
      return nack(StatusCode::BadChecksum, kNoField);
    }
    return ack();
  }

  void close() { open_ = false; }

  bool is_open() const { return open_; }
  uint8_t kind() const { return kind_; }
  const uint8_t* data() const { return buf_; }
  uint32_t size() const { return total_; }
  uint32_t next_offset() const { return next_; }

 private:
  XferReply ack() const {
    XferReply r;
    r.ack.kind = kind_;
    r.ack.next_offset = open_ ? next_ : 0;
    r.ack.total_size = open_ ? total_ : 0;
    return r;
  }
  static XferReply nack(StatusCode s, uint8_t field) {
    XferReply r;
    r.status = s;
    r.field = field;
    return r;
  }

  uint8_t kind_;
  uint8_t* buf_;
  size_t cap_;
  bool open_ = false;
  uint32_t total_ = 0;
  uint32_t crc_expected_ = 0;
  uint32_t next_ = 0;
  Crc32 crc_;
};

}  // namespace nlsoft::protocol
