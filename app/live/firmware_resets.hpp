#pragma once
// Reset forensics: a firmware that started again behind a reconnect (its
// uptime went back, or its parameter list changed) has forgotten this
// session's edits; which ones are named, and can be sent again. Separate
// because it is decided on the link's threads, from STATUS and the
// re-handshake, while the user acts on it later from the UI or a script.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "app/link/device.hpp"
#include "app/live/active_run.hpp"
#include "app/live/live_params.hpp"
#include "app/live/notices.hpp"

namespace nlsoft::console {

class FirmwareResets {
 public:
  FirmwareResets(Device& device, LiveParams& params, ActiveRun& run, Notices& notices)
      : device_(device), params_(params), run_(run), notices_(notices) {}

  // Called by LiveConsole: each STATUS's uptime (the reader thread), the
  // link going down, and after a re-handshake (the link's thread, or
  // whoever reconnects a new simulator).
  void note_uptime(uint32_t uptime_ms);
  void link_down() { boot_at_down_ns_ = boot_ns_.load(); }
  // Did the firmware reset, and which edits did it lose? Says so.
  void check(const protocol::Info& before, const protocol::Info& now, const protocol::Status& st);

  // Any thread. The TUI redraws its parameter panel when the count moves.
  uint32_t count() const { return resets_.load(); }
  std::vector<std::string> forgotten() const;  // "Q is 1e6 (this session set 2e6)"
  // Sends the session's edits again, in the order they were made, and
  // returns what it sent.
  std::vector<std::string> reapply();

 private:
  Device& device_;
  LiveParams& params_;
  ActiveRun& run_;
  Notices& notices_;
  mutable std::mutex mu_;
  std::vector<std::string> forgotten_;
  std::atomic<uint32_t> resets_{0};
  // When the firmware booted, on our steady clock, from the last STATUS's
  // uptime; and that estimate when the link went down. A later boot after a
  // reconnect is a reset, whatever the uptimes themselves are.
  std::atomic<int64_t> boot_ns_{0};
  std::atomic<int64_t> boot_at_down_ns_{0};
};

}  // namespace nlsoft::console
