#pragma once
// Outgoing bytes between the protocol and the HAL: a ring the firmware
// fills with whole frames and drains as fast as the port takes bytes.
// Telemetry is admitted only while room for a reply stays free, so a burst of
// telemetry can never starve the answer to a request or a heartbeat.
#include <cstddef>
#include <cstdint>

#include "firmware/core/hal.hpp"

namespace nlsoft::fw {

template <size_t Capacity>
class TxQueue {
 public:
  static constexpr size_t kReserve = 160;  // two replies or a STATUS + a LOG
  static_assert(Capacity > kReserve + 256, "room for a telemetry frame above the reserve");

  size_t room() const { return Capacity - used_; }

  // Whole frame or nothing. Droppable frames (telemetry, log) must leave the
  // reserve free.
  bool push(const uint8_t* frame, size_t len, bool droppable) {
    const size_t need = len + (droppable ? kReserve : 0);
    if (need > room()) return false;
    for (size_t i = 0; i < len; ++i) buf_[(head_ + used_ + i) % Capacity] = frame[i];
    used_ += len;
    return true;
  }

  // Droppable frames queued together or not at all (a SENSOR_SAMPLE, its
  // sample frame and its SENSOR_HEALTH): none ever arrives without the
  // others. A length of 0 is a frame left out.
  bool push_group(const uint8_t* const* frames, const size_t* lens, int count) {
    size_t total = 0;
    for (int i = 0; i < count; ++i) total += lens[i];
    if (total + kReserve > room()) return false;
    for (int i = 0; i < count; ++i)
      if (lens[i] > 0) push(frames[i], lens[i], false);
    return true;
  }

  // Hands the HAL as much as it takes, in at most two contiguous pieces.
  void drain(Hal& hal) {
    while (used_ > 0) {
      const size_t run = head_ + used_ <= Capacity ? used_ : Capacity - head_;
      const size_t sent = hal.serial_write(buf_ + head_, run);
      head_ = (head_ + sent) % Capacity;
      used_ -= sent;
      if (sent < run) break;
    }
  }

 private:
  uint8_t buf_[Capacity];
  size_t head_ = 0, used_ = 0;
};

}  // namespace nlsoft::fw
