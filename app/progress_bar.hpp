#pragma once
// A one-line progress bar on stderr, drawn only when stderr is a terminal
// so logs and CI output stay clean. Header-only: twenty lines are not worth
// a dependency. One bar is drawn at a time.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace nlsoft::console {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label) : label_(std::move(label)), tty_(isatty(STDERR_FILENO) != 0) {}
  ~ProgressBar() { finish(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // `note`: what is being done now, after the bar ("compiling main.cpp").
  void update(long done, long total, const std::string& note = "") {
    if (!tty_ || total <= 0) return;
    const double f = double(done) / double(total);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const int width = 30, filled = int(f * width);
    std::lock_guard<std::mutex> lock(mu());
    text_ = label_ + " [" + std::string(size_t(filled), '#') + std::string(size_t(width - filled), '.') + "] " +
            tail(f, elapsed) + note;
    std::fprintf(stderr, "\r%s\033[K", text_.c_str());
    std::fflush(stderr);
    shown() = this;
  }
  // "  42%  ETA   12s ": no ETA where there is nothing to extrapolate from,
  // or nothing left to count (a build's last step, linking, takes seconds
  // at 100 %, which an ETA showed as "0s").
  static std::string tail(double fraction, double elapsed_s) {
    char out[64];
    if (fraction > 0 && fraction < 1)
      std::snprintf(out, sizeof out, "%3d%%  ETA %4.0fs ", int(fraction * 100), elapsed_s * (1 - fraction) / fraction);
    else
      std::snprintf(out, sizeof out, "%3d%%  ", int(fraction * 100));
    return out;
  }

  void finish() {
    std::lock_guard<std::mutex> lock(mu());
    if (shown() != this) return;
    std::fprintf(stderr, "\r\033[K");
    shown() = nullptr;
  }

  // A line for stderr from any thread (the firmware's log, a link notice):
  // a bar on the terminal is cleared first and drawn again under the line,
  // so the two never share a line ("ETA 0s firmware info: ...").
  // `out`: stdout for a program's results, which share the terminal.
  static void say(const std::string& line, std::FILE* out = stderr) {
    std::lock_guard<std::mutex> lock(mu());
    const ProgressBar* bar = shown();
    if (bar) std::fprintf(stderr, "\r\033[K"), std::fflush(stderr);
    std::fprintf(out, "%s\n", line.c_str());
    std::fflush(out);
    if (bar) std::fprintf(stderr, "%s", bar->text_.c_str()), std::fflush(stderr);
  }

 private:
  static std::mutex& mu() {
    static std::mutex m;
    return m;
  }
  static const ProgressBar*& shown() {  // the bar on the terminal's last line, if any
    static const ProgressBar* bar = nullptr;
    return bar;
  }

  std::string label_;
  bool tty_;
  std::string text_;  // as last drawn
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace nlsoft::console
