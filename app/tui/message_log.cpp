#include "app/tui/message_log.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>

#include "app/record/utc_time.hpp"
#include "app/tui/fit_text.hpp"
#include "host/files/printable.hpp"

namespace nlsoft::console::tui {

using host::printable;

namespace {
constexpr size_t kKeep = 2000;
const char* role_tag(Role r) {
  switch (r) {
    case Role::Error: return "error";
    case Role::Warn: return "warn";
    case Role::Ok: return "ok";
    default: return "info";
  }
}
}  // namespace

std::string session_log_path(const std::string& db_path) {
  const size_t slash = db_path.rfind('/');
  const size_t dot = db_path.rfind('.');
  const std::string stem = dot != std::string::npos && (slash == std::string::npos || dot > slash) ? db_path.substr(0, dot) : db_path;
  return stem + ".session.log";
}

MessageLog::MessageLog(const std::string& file) : file_(file) {
  if (file_.empty()) return;
  out_ = std::fopen(file_.c_str(), "a");
  if (!out_) {
    add(fmt::format("session log {} not written: {}", file_, std::strerror(errno)), Role::Warn);
    file_.clear();
    return;
  }
  std::fprintf(out_, "--- %s session start\n", utc_now().c_str());
  std::fflush(out_);
}

MessageLog::~MessageLog() {
  if (!out_) return;
  if (unwritten_ > 0)
    std::fprintf(out_, "%s warn  %llu messages not written: the session log holds at most %zu bytes a session\n",
                 utc_now().c_str(), static_cast<unsigned long long>(unwritten_), kMaxFileBytes);
  std::fclose(out_);
}

void MessageLog::add(const std::string& text, Role role) {
  const std::string stamp = utc_now();  // 2026-11-23T09:45:02.123Z
  std::lock_guard<std::mutex> lock(mu_);
  entries_.push_back({stamp.size() >= 19 ? stamp.substr(11, 8) : stamp, text, role});
  if (entries_.size() > kKeep) entries_.pop_front();
  if (out_) {
    // Through the one escaping function: whatever a message quotes cannot
    // act on the terminal that later shows the file, nor split a line.
    const std::string line = fmt::format("{} {:<5} {}\n", stamp, role_tag(role), printable(text));
    if (written_ + line.size() > kMaxFileBytes) {
      // Bounded, with a count of what was left out (said at the end).
      ++unwritten_;
      return;
    }
    written_ += line.size();
    std::fputs(line.c_str(), out_);
    std::fflush(out_);  // a crash keeps what was said up to it
  }
}

MessageLog::Entry MessageLog::last() const {
  std::lock_guard<std::mutex> lock(mu_);
  return entries_.empty() ? Entry{"", "", Role::Normal} : entries_.back();
}

size_t MessageLog::size() const {
  std::lock_guard<std::mutex> lock(mu_);
  return entries_.size();
}

void MessageLog::draw(const Screen& screen, int y, int x, int h, int w, bool focused, size_t back) const {
  std::lock_guard<std::mutex> lock(mu_);
  put(y, x, fmt::format(" Messages ({}) ", entries_.size()), w, screen.attr(focused ? Role::Title : Role::KeyName));
  const int body = h - 2;
  if (body <= 0) return;
  back = std::min(back, entries_.size() > 0 ? entries_.size() - 1 : size_t(0));
  // Bottom up from the newest shown: each message whole, wrapped under its
  // text; the oldest one that does not fit loses its first lines.
  const int text_w = std::max(1, w - 11);
  int row = y + body + 1;  // one below the last row the messages take
  for (size_t i = entries_.size() - back; i > 0 && row > y + 1; --i) {
    const Entry& e = entries_[i - 1];
    const std::vector<std::string> lines = wrap_words(e.text, size_t(text_w));
    for (size_t l = lines.size(); l > 0 && row > y + 1; --l) {
      --row;
      if (l == 1) put(row, x + 1, e.time, 8, screen.attr(Role::Dim));
      put(row, x + 10, lines[l - 1], text_w, screen.attr(e.role));
    }
  }
  put(y + h - 1, x,
      back > 0 ? fmt::format("Up/Down PgUp/PgDn scroll, End newest ({} newer)", back)
               : (file_.empty() ? std::string("Up/Down PgUp/PgDn scroll back")
                              : "log: " + elide_path(file_, size_t(std::max(0, w - 5)), screen.ellipsis())),
      w, screen.attr(Role::Dim));
}

}  // namespace nlsoft::console::tui
