// Reset forensics: a firmware that started again behind a reconnect (its
// uptime went back, or its parameter list changed) has forgotten this
// session's edits; which ones are named, and can be sent again.
#include "app/live/live_console.hpp"

#include <fmt/format.h>

#include <chrono>

#include "app/live/param_text.hpp"

namespace nlsoft::console {

namespace p = nlsoft::protocol;

void LiveConsole::note_uptime(uint32_t uptime_ms) {
  boot_ns_ = std::chrono::steady_clock::now().time_since_epoch().count() - int64_t(uptime_ms) * 1000000;
}

void LiveConsole::check_for_reset(const p::Info& before, const p::Info& now, const p::Status& st) {
  const int64_t was = boot_at_down_ns_.load();
  note_uptime(st.uptime_ms);
  // Half a second absorbs the reply latency in the estimates.
  constexpr int64_t kSlackNs = 500000000;
  std::string why;
  if (was != 0 && boot_ns_.load() - was > kSlackNs)
    why = fmt::format("its uptime says it started again {:.1f} s ago", st.uptime_ms / 1000.0);
  else if (now.param_hash != before.param_hash)
    why = "its parameter list changed";
  if (why.empty()) return;
  const auto all = device_->get_all();
  std::vector<std::string> forgotten;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const auto& [info, mine] : edits_) {
      for (const auto& [fi, theirs] : all) {
        if (fi.name != info.name) continue;
        bool same = theirs.size() == mine.size();
        for (size_t i = 0; same && i < mine.size(); ++i) same = float(theirs[i]) == float(mine[i]);
        if (!same)
          forgotten.push_back(fmt::format("{} is {} (this session set {})", info.name, format_param_values(fi, theirs),
                                          format_param_values(info, mine)));
      }
    }
    forgotten_ = forgotten;
  }
  ++firmware_resets_;
  say(fmt::format("the firmware has reset ({}): parameters re-read; {}", why,
                  forgotten.empty() ? "none of this session's edits was lost"
                                    : fmt::format("{} edit{} no longer in force; `params reapply` (A in the parameter "
                                                  "panel) sends them again",
                                                  forgotten.size(), forgotten.size() == 1 ? " is" : "s are")));
  for (const std::string& f : forgotten) say("  " + f);
  if (recorder_) recorder_->add_link_event(run_id_.load(), "reset", why);
}

std::vector<std::string> LiveConsole::forgotten_edits() const {
  std::lock_guard<std::mutex> lock(mu_);
  return forgotten_;
}

std::vector<std::string> LiveConsole::reapply_edits() {
  std::vector<std::pair<ParamInfo, std::vector<double>>> edits;
  {
    std::lock_guard<std::mutex> lock(mu_);
    edits = edits_;
  }
  std::vector<std::string> sent;
  for (const auto& [info, values] : edits) {
    // The catalog may have changed with the firmware: send by today's entry.
    const ParamInfo* now = device_->catalog()->find(info.name);
    if (!now) {
      sent.push_back(fmt::format("{}: no longer a parameter of this firmware; skipped", info.name));
      continue;
    }
    const auto echoed = apply_param(*now, values);
    sent.push_back(fmt::format("{} = {}", now->name, format_param_values(*now, echoed)));
  }
  std::lock_guard<std::mutex> lock(mu_);
  forgotten_.clear();
  return sent;
}

}  // namespace nlsoft::console
