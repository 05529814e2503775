// A lock-free atomic, not a volatile sig_atomic_t: the handler runs on the
// main thread while the worker's run_for reads it, and a lock-free atomic
// is both async-signal-safe and free of that data race.
#include "app/live/interrupt.hpp"

#include <fmt/format.h>

#include <atomic>

namespace nlsoft::console {

namespace {

std::atomic<int>& interrupted_flag() {
  static_assert(std::atomic<int>::is_always_lock_free, "the signal handler must not take a lock");
  static std::atomic<int> flag{0};
  return flag;
}

}  // namespace

void request_interrupt(int signal) { interrupted_flag() = signal; }

bool interrupted() { return interrupted_flag() != 0; }

std::string interrupt_reason() {
  switch (interrupted_flag().load()) {
    case SIGINT: return "interrupted by SIGINT (Ctrl-C)";
    case SIGTERM: return "interrupted by SIGTERM";
    case SIGHUP: return "interrupted by SIGHUP (the terminal closed or the connection dropped)";
    case SIGPIPE: return "interrupted by SIGPIPE (standard output's reader is gone)";
    case 0: return "not interrupted";
    default: return fmt::format("interrupted by signal {}", interrupted_flag().load());
  }
}

}  // namespace nlsoft::console
