#include "app/live/log_limiter.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace nlsoft::console {

bool LogLimiter::admit(std::chrono::steady_clock::time_point now, std::string& dropped_words) {
  dropped_words.clear();
  if (started_) {
    const double dt = std::chrono::duration<double>(now - last_).count();
    tokens_ = std::min(kBurst, tokens_ + std::max(0.0, dt) * kPerSecond);
  }
  started_ = true;
  last_ = now;
  if (tokens_ < 1) {
    ++dropped_;
    ++dropped_total_;
    return false;
  }
  tokens_ -= 1;
  if (dropped_ > 0)
    dropped_words = fmt::format("{} firmware LOG line{} not shown (more than {:g} a second)", dropped_,
                                dropped_ == 1 ? "" : "s", kPerSecond);
  dropped_ = 0;
  return true;
}

}  // namespace nlsoft::console
