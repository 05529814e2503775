#pragma once
// The bottom lines that are always visible: link statistics, and the
// function-key bar (htop style).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "app/link/link_stats.hpp"
#include "app/tui/fit_text.hpp"
#include "app/tui/screen.hpp"

namespace nlsoft::console::tui {

// "link up /dev/pts/3 | 2.6k fr/s 92 kB/s | crc 0 err 0 | lost 0 | loop 130.0 Hz | step 55 us (max 329)",
// field by field, each with how long it stays on a narrow bar.
std::vector<Field> status_fields(const LinkStats& s, const std::string& port);
// `alert` (e.g. invalid_sensors_words) follows the link's state, kept
// before every other field, and turns the bar to a warning.
void draw_status_bar(const Screen& screen, int y, int w, const LinkStats& s, const std::string& port,
                     const std::string& alert);
// "sensors invalid: b1x b1y b1z" from SENSOR_HEALTH's mask and the rig's
// sensor names, in channel order; empty when every channel is valid.
std::string invalid_sensors_words(uint32_t invalid, const std::vector<std::string>& names);
// The function-key bar: every key on any width the console draws on (60
// columns up), with its label where there is room.
// With `restart` (the simulator has ended), R Restart leads the bar.
void draw_key_bar(const Screen& screen, int y, int w, bool restart = false);
// (key, label) in bar order for a bar w columns wide.
std::vector<std::pair<std::string, std::string>> key_bar_items(int w, bool restart = false);

}  // namespace nlsoft::console::tui
