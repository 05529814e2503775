#include "app/tui/status_bar.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "app/tui/key_table.hpp"

namespace nlsoft::console::tui {

namespace {
std::string si(double v) {
  if (v >= 1e6) return fmt::format("{:.1f}M", v / 1e6);
  if (v >= 1e4) return fmt::format("{:.1f}k", v / 1e3);
  return fmt::format("{:.0f}", v);
}
}  // namespace

// Their keep: the link's state first, then what tells of a fault (a
// firmware dropping or overrunning, frames lost), the throughput last.
std::vector<Field> status_fields(const LinkStats& s, const std::string& port) {
  const char* state = !s.connected ? "LINK DOWN" : s.silent ? "link silent" : "link up";
  std::vector<Field> f = {{fmt::format("{} {}", state, port), 20},
                          {fmt::format("{} fr/s {}B/s", si(s.frames_per_s), si(s.bytes_per_s)), 1},
                          {fmt::format("crc {} err {}", s.crc_errors, s.decode_errors), 4},
                          {fmt::format("lost {}", s.lost_telemetry), 6},
                          {fmt::format("loop {:.1f} Hz", s.loop_rate_hz), 7}};
  if (s.have_status) f.push_back({fmt::format("step {:.0f} us (max {:.0f})", s.compute_mean_us, s.compute_max_us), 3});
  if (s.timeouts || s.retransmits) f.push_back({fmt::format("retries {} timeouts {}", s.retransmits, s.timeouts), 5});
  if (s.fw_tx_dropped || s.fw_loop_overruns)
    f.push_back({fmt::format("fw dropped {} overruns {}", s.fw_tx_dropped, s.fw_loop_overruns), 8});
  if (s.reconnects) f.push_back({fmt::format("reconnects {}", s.reconnects), 2});
  return f;
}

void draw_status_bar(const Screen& screen, int y, int w, const LinkStats& s, const std::string& port,
                     const std::string& alert) {
  const Role role = !s.connected ? Role::Error : s.silent || !alert.empty() ? Role::Warn : Role::Title;
  std::vector<Field> fields = status_fields(s, port);
  fields.front().text = " " + fields.front().text;
  if (!alert.empty()) fields.insert(fields.begin() + 1, Field{alert, 19});
  fill_row(y, 0, w, screen.attr(role));
  put(y, 0, fit_fields(fields, " | ", size_t(w), screen.ellipsis()), w, screen.attr(role));
}

std::string invalid_sensors_words(uint32_t invalid, const std::vector<std::string>& names) {
  std::string words;
  for (size_t i = 0; i < 32; ++i)
    if (invalid >> i & 1u) words += " " + (i < names.size() ? names[i] : fmt::format("l{}", i));
  return words.empty() ? words : "sensors invalid:" + words;
}

std::vector<std::pair<std::string, std::string>> key_bar_items(int w, bool restart) {
  const std::vector<const KeyBinding*> keys = bar_bindings(restart);
  std::vector<std::string> names;
  int last_keep = 0;  // the label the bar keeps longest
  for (const KeyBinding* k : keys) {
    names.push_back(k->keys.front().name);
    last_keep = std::max(last_keep, k->keep);
  }
  const size_t kKeyCount = keys.size();
  std::vector<std::pair<std::string, std::string>> items;
  // htop's look when it fits: each label padded to 7 columns.
  int width = 0;
  for (const std::string& n : names) width += int(n.size()) + 7;
  if (width <= w) {
    for (size_t i = 0; i < kKeyCount; ++i) items.emplace_back(names[i], fmt::format("{:<7}", keys[i]->label));
    return items;
  }
  // Narrower: every key stays; brief labels one space apart, and where even
  // those do not fit the least needed labels go, so the keys never do.
  std::vector<std::string> labels;
  for (const KeyBinding* k : keys) labels.emplace_back(k->brief);
  auto total = [&] {
    int t = 0;
    for (size_t i = 0; i < kKeyCount; ++i) t += int(names[i].size() + labels[i].size()) + 1;
    return t - 1;
  };
  for (int keep = 0; keep <= last_keep && total() > w; ++keep)
    for (size_t i = 0; i < kKeyCount; ++i)
      if (keys[i]->keep == keep) labels[i].clear();
  for (size_t i = 0; i < kKeyCount; ++i)
    items.emplace_back(names[i], i + 1 < kKeyCount ? labels[i] + " " : labels[i]);
  return items;
}

void draw_key_bar(const Screen& screen, int y, int w, bool restart) {
  fill_row(y, 0, w, 0);
  int x = 0;
  for (const auto& [k, label] : key_bar_items(w, restart)) {
    if (x >= w) break;
    put(y, x, k, w - x, screen.attr(Role::KeyName));
    x += int(k.size());
    put(y, x, label, w - x, screen.attr(Role::KeyLabel));
    x += int(label.size());
  }
}

}  // namespace nlsoft::console::tui
