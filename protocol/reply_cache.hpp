#pragma once
// The firmware's memory of its last reply (PROTOCOL.md, section 10): a
// request whose seq, type and payload equal the previous request's is a
// retransmission, answered with the stored reply and not executed again.
// That makes non-idempotent requests (XFER_COMMIT, RUN_START) safe when only
// the reply was lost. The payload takes part so that a console restarted
// with the same seq and a different request (RUN_START with a new run id) is
// executed, not answered with the old reply.

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "protocol/crc.hpp"
#include "protocol/frame.hpp"

namespace nlsoft::protocol {

class ReplyCache {
 public:
  // Largest replies on the wire: RIG_INFO with a full shape list, 128
  // bytes (protocol 1.2); INFO_EX with a 32-byte name, 78 bytes;
  // PARAM_VALUE with 16 values, 76 bytes. RIG_INFO is idempotent and would
  // do without the cache, but a reply left out would make the retransmission
  // rule depend on the message type.
  static constexpr size_t kCapacity = 128;

  // True when `request` repeats the previous request; then wire/size give
  // the reply to send again.
  bool find(const FrameView& request, const uint8_t*& wire, size_t& size) const {
    if (!valid_ || request.header.seq != seq_ || request.header.type != type_ ||
        request.header.length != length_ || body_crc(request) != crc_)
      return false;
    wire = reply_;
    size = size_;
    return true;
  }

  // Records the reply just sent for `request` (an encoded wire frame).
  void store(const FrameView& request, const uint8_t* wire, size_t size) {
    valid_ = size != 0 && size <= kCapacity;
    if (!valid_) return;
    seq_ = request.header.seq;
    type_ = request.header.type;
    length_ = request.header.length;
    crc_ = body_crc(request);
    std::memcpy(reply_, wire, size);
    size_ = size;
  }

  void clear() { valid_ = false; }

 private:
  static uint16_t body_crc(const FrameView& f) {
    return f.header.length ? crc16(f.payload, f.header.length) : 0xFFFFu;
  }

  uint8_t reply_[kCapacity] = {};
  size_t size_ = 0;
  uint8_t seq_ = 0;
  uint8_t type_ = 0;
  uint8_t length_ = 0;
  uint16_t crc_ = 0;
  bool valid_ = false;
};

}  // namespace nlsoft::protocol
