#include "app/tui/message_log.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>

#include "app/record/utc_time.hpp"

namespace nlsoft::console::tui {

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
  if (out_) std::fclose(out_);
}

void MessageLog::add(const std::string& text, Role role) {
  const std::string stamp = utc_now();  // 2026-11-23T09:45:02.123Z
  std::lock_guard<std::mutex> lock(mu_);
  entries_.push_back({stamp.size() >= 19 ? stamp.substr(11, 8) : stamp, text, role});
  if (entries_.size() > kKeep) entries_.pop_front();
  if (out_) {
    std::fprintf(out_, "%s %-5s %s\n", stamp.c_str(), role_tag(role), text.c_str());
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
  back = std::min(back, entries_.size() > size_t(body) ? entries_.size() - size_t(body) : size_t(0));
  const size_t end = entries_.size() - back;
  const size_t begin = end > size_t(body) ? end - size_t(body) : 0;
  for (size_t i = begin; i < end; ++i) {
    const Entry& e = entries_[i];
    const int ry = y + 1 + int(i - begin);
    put(ry, x + 1, e.time, 8, screen.attr(Role::Dim));
    put(ry, x + 10, e.text, w - 11, screen.attr(e.role));
  }
  put(y + h - 1, x,
      back > 0 ? fmt::format("Up/Down PgUp/PgDn scroll, End newest ({} newer)", back)
               : (file_.empty() ? std::string("Up/Down PgUp/PgDn scroll back") : "log: " + file_),
      w, screen.attr(Role::Dim));
}

}  // namespace nlsoft::console::tui
