#pragma once
// Every message the console showed this session, with its time: the last
// one on the message row, all of them (up to 2000) in the log pane (F9),
// which scrolls back, and each appended to a session log file beside the
// database, so what the console said survives the terminal.
#include <cstdint>
#include <cstdio>
#include <deque>
#include <mutex>
#include <string>

#include "app/tui/screen.hpp"

namespace nlsoft::console::tui {

class MessageLog {
 public:
  // What one session may add to the file: a flood of messages (a firmware
  // that logs every step) stops there.
  static constexpr size_t kMaxFileBytes = size_t(8) << 20;
  // file: where to append ("" keeps the log in memory only). A file that
  // cannot be opened is reported as the first message, not fatal.
  explicit MessageLog(const std::string& file);
  ~MessageLog();
  MessageLog(const MessageLog&) = delete;
  MessageLog& operator=(const MessageLog&) = delete;

  // Any thread.
  void add(const std::string& text, Role role);
  struct Entry {
    std::string time, text;  // time: HH:MM:SS UTC
    Role role;
  };
  Entry last() const;
  const std::string& file() const { return file_; }

  // The pane: newest at the bottom; `back` entries scrolled back from the
  // newest (clamped).
  void draw(const Screen& screen, int y, int x, int h, int w, bool focused, size_t back) const;
  size_t size() const;

 private:
  mutable std::mutex mu_;
  std::deque<Entry> entries_;
  std::string file_;
  std::FILE* out_ = nullptr;
  size_t written_ = 0;     // bytes this session wrote to the file
  uint64_t unwritten_ = 0;  // messages past the cap, not written
};

// "runs.db" -> "runs.session.log" beside it.
std::string session_log_path(const std::string& db_path);

}  // namespace nlsoft::console::tui
