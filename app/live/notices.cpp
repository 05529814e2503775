// What is said before anyone listens (the TUI listens from its start, after
// connect()) waits for the first listener.
#include "app/live/notices.hpp"

namespace nlsoft::console {

void Notices::listen(Listener l) {
  std::lock_guard<std::mutex> lock(mu_);
  listener_ = std::move(l);
  if (!listener_) return;
  for (const std::string& s : unheard_) listener_(s);
  unheard_.clear();
}

void Notices::say(const std::string& s) {
  std::lock_guard<std::mutex> lock(mu_);
  if (listener_) listener_(s);
  else if (unheard_.size() < 32) unheard_.push_back(s);
}

}  // namespace nlsoft::console
