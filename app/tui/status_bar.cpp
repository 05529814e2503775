#include "app/tui/status_bar.hpp"

#include <fmt/format.h>

namespace nlsoft::console::tui {

namespace {
std::string si(double v) {
  if (v >= 1e6) return fmt::format("{:.1f}M", v / 1e6);
  if (v >= 1e4) return fmt::format("{:.1f}k", v / 1e3);
  return fmt::format("{:.0f}", v);
}
}  // namespace

std::string status_text(const LinkStats& s, const std::string& port) {
  const char* state = !s.connected ? "LINK DOWN" : s.silent ? "link silent" : "link up";
  std::string t = fmt::format("{} {} | {} fr/s {}B/s | crc {} err {} | lost {} | loop {:.1f} Hz", state, port,
                              si(s.frames_per_s), si(s.bytes_per_s), s.crc_errors, s.decode_errors, s.lost_telemetry,
                              s.loop_rate_hz);
  if (s.have_status) t += fmt::format(" | step {:.0f} us (max {:.0f})", s.compute_mean_us, s.compute_max_us);
  if (s.timeouts || s.retransmits) t += fmt::format(" | retries {} timeouts {}", s.retransmits, s.timeouts);
  if (s.fw_tx_dropped || s.fw_loop_overruns) t += fmt::format(" | fw dropped {} overruns {}", s.fw_tx_dropped, s.fw_loop_overruns);
  if (s.reconnects) t += fmt::format(" | reconnects {}", s.reconnects);
  return t;
}

void draw_status_bar(const Screen& screen, int y, int w, const LinkStats& s, const std::string& port) {
  const Role role = !s.connected ? Role::Error : s.silent ? Role::Warn : Role::Title;
  fill_row(y, 0, w, screen.attr(role));
  put(y, 0, " " + status_text(s, port), w, screen.attr(role));
}

void draw_key_bar(const Screen& screen, int y, int w) {
  static const std::pair<const char*, const char*> keys[] = {
      {"F1", "Help"}, {"F2", "Params"}, {"F3", "Ref"}, {"F4", "Runs"}, {"F5", "Start"},
      {"F6", "Stop"}, {"F7", "Hold"},   {"F8", "Neutral"}, {":", "Cmd"}, {"v", "View"}, {"q", "Quit"}};
  fill_row(y, 0, w, 0);
  int x = 0;
  for (const auto& [k, label] : keys) {
    if (x >= w) break;
    put(y, x, k, w - x, screen.attr(Role::KeyName));
    x += int(std::string(k).size());
    const std::string l = fmt::format("{:<7}", label);
    put(y, x, l, w - x, screen.attr(Role::KeyLabel));
    x += int(l.size());
  }
}

}  // namespace nlsoft::console::tui
