#pragma once
// A one-line progress bar on stderr, drawn only when stderr is a terminal
// so logs and CI output stay clean. Header-only: twenty lines are not worth
// a dependency.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace nlsoft::console {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label) : label_(std::move(label)), tty_(isatty(STDERR_FILENO) != 0) {}
  ~ProgressBar() { finish(); }

  void update(long done, long total) {
    if (!tty_ || total <= 0) return;
    const double f = double(done) / double(total);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double eta = f > 0 ? elapsed * (1 - f) / f : 0;
    const int width = 30, filled = int(f * width);
    std::fprintf(stderr, "\r%s [%s%s] %3d%%  ETA %4.0fs ", label_.c_str(), std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(width - filled), '.').c_str(), int(f * 100), eta);
    std::fflush(stderr);
    drawn_ = true;
  }
  void finish() {
    if (drawn_) std::fprintf(stderr, "\r\033[K");
    drawn_ = false;
  }

 private:
  std::string label_;
  bool tty_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace nlsoft::console
