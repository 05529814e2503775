// A reset is told from a boot later than the one seen before the link
// went down, or a parameter list that changed; the edits it lost are the
// session's edits whose values the firmware no longer holds.
#include "app/live/firmware_resets.hpp"

#include <fmt/format.h>

#include <chrono>

#include "app/live/param_text.hpp"

namespace nlsoft::console {

namespace p = nlsoft::protocol;

void FirmwareResets::note_uptime(uint32_t uptime_ms) {
  boot_ns_ = std::chrono::steady_clock::now().time_since_epoch().count() - int64_t(uptime_ms) * 1000000;
}

void FirmwareResets::check(const p::Info& before, const p::Info& now, const p::Status& st) {
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
  const auto all = device_.get_all();
  std::vector<std::string> forgotten;
  for (const auto& [info, mine] : params_.edits()) {
    for (const auto& [fi, theirs] : all) {
      if (fi.name != info.name) continue;
      if (!same_param_values(theirs, mine))
          forgotten.push_back(fmt::format("{} is {} (this session set {})", info.name, format_param_values(fi, theirs),
                                        format_param_values(info, mine)));
    }
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    forgotten_ = forgotten;
  }
  ++resets_;
  notices_.say(fmt::format("the firmware has reset ({}): parameters re-read; {}", why,
                  forgotten.empty() ? "none of this session's edits was lost"
                                    : fmt::format("{} edit{} no longer in force; `params reapply` (A in the parameter "
                                                  "panel) sends them again",
                                                  forgotten.size(), forgotten.size() == 1 ? " is" : "s are")));
  for (const std::string& f : forgotten) notices_.say("  " + f);
  run_.recorder.add_link_event(run_.id.load(), "reset", why);
}

std::vector<std::string> FirmwareResets::forgotten() const {
  std::lock_guard<std::mutex> lock(mu_);
  return forgotten_;
}

std::vector<std::string> FirmwareResets::reapply() {
  std::vector<std::string> sent;
  for (const auto& [info, values] : params_.edits()) {
    // The catalog may have changed with the firmware: send by today's entry.
    const ParamInfo* now = device_.catalog()->find(info.name);
    if (!now) {
      sent.push_back(fmt::format("{}: no longer a parameter of this firmware; skipped", info.name));
      continue;
    }
    const auto echoed = params_.apply(*now, values);
    sent.push_back(fmt::format("{} = {}", now->name, format_param_values(*now, echoed)));
  }
  std::lock_guard<std::mutex> lock(mu_);
  forgotten_.clear();
  return sent;
}

}  // namespace nlsoft::console
