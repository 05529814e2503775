#pragma once
// The steady clock in nanoseconds, as the link's atomics keep times (a
// time_point is not lock-free to store in a std::atomic everywhere).
#include <chrono>
#include <cstdint>

namespace nlsoft::console {

inline int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace nlsoft::console
