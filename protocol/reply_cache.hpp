#pragma once
// The firmware's memory of its last reply (PROTOCOL.md, section 10): a
// request whose seq and type equal the previous request's is a
// retransmission, answered with the stored reply and not executed again.
// That makes non-idempotent requests (XFER_COMMIT, RUN_START) safe when only
// the reply was lost.

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "protocol/frame.hpp"

namespace nlsoft::protocol {

class ReplyCache {
 public:
  // Largest reply on the wire is PARAM_VALUE with 16 values: 76 bytes.
  static constexpr size_t kCapacity = 80;

  // True when `request` repeats the previous request; then wire/size give
  // the reply to send again.
  bool find(const Header& request, const uint8_t*& wire, size_t& size) const {
    if (!valid_ || request.seq != seq_ || request.type != type_) return false;
    wire = reply_;
    size = size_;
    return true;
  }

  // Records the reply just sent for `request` (an encoded wire frame).
  void store(const Header& request, const uint8_t* wire, size_t size) {
    valid_ = size != 0 && size <= kCapacity;
    if (!valid_) return;
    seq_ = request.seq;
    type_ = request.type;
    std::memcpy(reply_, wire, size);
    size_ = size;
  }

  void clear() { valid_ = false; }

 private:
  uint8_t reply_[kCapacity] = {};
  size_t size_ = 0;
  uint8_t seq_ = 0;
  uint8_t type_ = 0;
  bool valid_ = false;
};

}  // namespace nlsoft::protocol
