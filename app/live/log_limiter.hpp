#pragma once
// The firmware's LOG lines, bounded: a firmware that floods LOG (a fault
// logged every step, a hostile one) would otherwise grow the session log
// and a headless console's standard error without end. Up to kBurst lines
// pass at once, then kPerSecond a second; the rest are counted, and the
// count is said with the next line that passes. Reader thread only.
#include <chrono>
#include <cstdint>
#include <string>

namespace nlsoft::console {

class LogLimiter {
 public:
  static constexpr double kPerSecond = 20;
  static constexpr double kBurst = 50;

  // Whether the line at `now` is shown; when it is and lines were dropped
  // before it, `dropped_words` says how many.
  bool admit(std::chrono::steady_clock::time_point now, std::string& dropped_words);
  uint64_t dropped_total() const { return dropped_total_; }

 private:
  double tokens_ = kBurst;
  bool started_ = false;
  std::chrono::steady_clock::time_point last_{};
  uint64_t dropped_ = 0, dropped_total_ = 0;
};

}  // namespace nlsoft::console
