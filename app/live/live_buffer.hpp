#pragma once
// The most recent samples, for the live plots: the link thread appends, the
// UI copies a snapshot at its own pace. Fixed capacity, so a 10 kHz loop
// costs a copy per frame and nothing grows.
#include <cstdint>
#include <limits>
#include <mutex>
#include <vector>

#include "app/record/sample.hpp"

namespace nlsoft::console {

class LiveBuffer {
 public:
  explicit LiveBuffer(size_t capacity = 4096) : ring_(capacity) {}

  void push(const Sample& s) {
    std::lock_guard<std::mutex> lock(mu_);
    ring_[head_] = s;
    head_ = (head_ + 1) % ring_.size();
    if (size_ < ring_.size()) ++size_;
    ++total_;
  }
  // SENSOR_HEALTH follows its step's sample: the sensor channels it flags
  // invalid become NaN in that sample, so a plot leaves a gap instead of
  // drawing the 0 the firmware sent. Another step's word changes nothing.
  void mark_invalid(uint32_t step, uint32_t invalid) {
    std::lock_guard<std::mutex> lock(mu_);
    if (size_ == 0 || invalid == 0) return;
    Sample& s = ring_[(head_ + ring_.size() - 1) % ring_.size()];
    if (!s.has(protocol::telemetry_field::kStep) || s.step != step) return;
    for (int i = 0; i < s.w && i < 32; ++i)
      if (invalid >> i & 1u) s.l[i] = std::numeric_limits<float>::quiet_NaN();
  }
  void clear() {
    std::lock_guard<std::mutex> lock(mu_);
    size_ = head_ = 0;
  }
  // Oldest first, at most `max` of the newest samples.
  std::vector<Sample> snapshot(size_t max) const {
    std::lock_guard<std::mutex> lock(mu_);
    const size_t n = std::min(max, size_);
    std::vector<Sample> out;
    out.reserve(n);
    for (size_t i = 0; i < n; ++i) out.push_back(ring_[(head_ + ring_.size() - n + i) % ring_.size()]);
    return out;
  }
  uint64_t total() const {
    std::lock_guard<std::mutex> lock(mu_);
    return total_;
  }

 private:
  mutable std::mutex mu_;
  std::vector<Sample> ring_;
  size_t head_ = 0, size_ = 0;
  uint64_t total_ = 0;
};

}  // namespace nlsoft::console
