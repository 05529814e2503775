#pragma once
// A LOG message's text built in place: fixed capacity, truncated at it,
// no allocation. Hand-written: snprintf would bring newlib's printf into
// images whose only formatted text is a number or two in a warning.
#include <cstddef>
#include <cstdint>

namespace nlsoft::fw {

template <size_t Cap>
class LogText {
 public:
  LogText& operator<<(const char* s) {
    while (*s != '\0' && len_ < Cap) buf_[len_++] = *s++;
    buf_[len_] = '\0';
    return *this;
  }
  LogText& operator<<(uint32_t v) {
    char digits[10];
    int n = 0;
    do {
      digits[n++] = char('0' + v % 10u);
      v /= 10u;
    } while (v != 0);
    while (n > 0 && len_ < Cap) buf_[len_++] = digits[--n];
    buf_[len_] = '\0';
    return *this;
  }
  const char* c_str() const { return buf_; }
  size_t size() const { return len_; }

 private:
  char buf_[Cap + 1] = {};
  size_t len_ = 0;
};

}  // namespace nlsoft::fw
