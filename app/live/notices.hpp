#pragma once
// What the console tells the user (link events, firmware LOG lines, the UDP
// stream's count, a run's early end), from whichever thread noticed it.
// Separate because every part of the console speaks, and whoever listens
// (the TUI's log, a headless console's standard error) comes and goes.
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace nlsoft::console {

class Notices {
 public:
  using Listener = std::function<void(const std::string& line)>;

  // What was said while none was set (up to 32 messages) goes to the next
  // one set; an empty listener detaches (the TUI before it tears down).
  void listen(Listener l);
  // Any thread; the listener is called under a lock, so it must not say
  // anything itself.
  void say(const std::string& s);

 private:
  std::mutex mu_;
  Listener listener_;
  std::vector<std::string> unheard_;
};

}  // namespace nlsoft::console
