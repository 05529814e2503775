#include "app/tui/list_cursor.hpp"
#include "app/tui/ref_panel.hpp"
#include "app/tui/fit_text.hpp"

#include <fmt/format.h>

#include "app/live/reference_spec.hpp"
#include "app/tui/curses.hpp"

namespace nlsoft::console::tui {

using host::reference_kind_name;

namespace {
struct Kind {
  const char* label;
  const char* preset;  // the reference's name (app/reference_names.cpp); nullptr for the CSV table
};
constexpr Kind kKinds[] = {{"Infinity", "infinity"}, {"Pringle", "pringle"}, {"Diagonal", "diagonal"},
                           {"Swirl", "swirl"},       {"Step", "steps"},      {"CSV", nullptr}};
constexpr size_t kKindCount = sizeof(kKinds) / sizeof(kKinds[0]);
}  // namespace

RefPanel::RefPanel(LiveConsole& console, Worker& worker, Ui& ui) : console_(console), worker_(worker), ui_(ui) {
  reset_kind();
}

void RefPanel::reset_kind() {
  selected_ = 0;
  if (!kKinds[kind_].preset) return;
  try {
    ref_ = reference_from_spec(console_.rig(), console_.device().info().loop_rate_hz, kKinds[kind_].preset, {});
  } catch (const std::exception& e) {
    ui_.message(e.what(), Role::Error);
  }
}

void RefPanel::select_kind(size_t kind) {
  if (kind == kind_) return;
  kind_ = kind;
  reset_kind();
}

void RefPanel::show_in_force() {
  if (const auto cur = console_.references().current()) {
    const bool table = cur->kind == RefKind::Table;
    for (size_t i = 0; i < kKindCount; ++i) {
      const bool match = table ? kKinds[i].preset == nullptr
                               : kKinds[i].preset && std::string(kKinds[i].preset) == reference_kind_name(cur->kind);
      if (!match) continue;
      kind_ = i;
      selected_ = 0;
      if (!table) ref_ = *cur;
      return;
    }
    return;  // a kind the panel has no page for (hold): leave it as it was
  }
  // Sent by nobody here: the firmware's start-up reference (the rig's paper
  // task) or one selected before this console connected.
  worker_.post("reading the reference in force", [this] {
    try {
      const uint8_t id = console_.device().status().ref_id;
      firmware_ref_id_ = id;
      for (size_t i = 0; i < kKindCount; ++i)
        if (kKinds[i].preset && id < kRefKindCount && RefKind(id) != RefKind::Table &&
            std::string(kKinds[i].preset) == reference_kind_name(RefKind(id)))
          firmware_kind_ = int(i);
    } catch (const std::exception& e) {
      ui_.message(std::string("reference in force: ") + e.what(), Role::Error);
    }
  });
}

std::vector<std::string> RefPanel::keys() const {
  if (!kKinds[kind_].preset) return {"file", "hold"};
  return reference_keys_for(ref_.kind);
}

void RefPanel::send() {
  if (!kKinds[kind_].preset) {
    const std::string path = csv_path_;
    const uint16_t hold = csv_hold_;
    uploading_ = true;
    up_done_ = 0;
    up_total_ = 0;
    worker_.post("uploading " + path, [this, path, hold] {
      try {
        console_.references().upload_table(path, hold, [this](size_t d, size_t t) {
          up_done_ = d;
          up_total_ = t;
        });
        ui_.message(fmt::format("table {} uploaded and selected", path), Role::Ok);
      } catch (const std::exception& e) {
        ui_.message(std::string("upload failed, the previous reference stays: ") + e.what(), Role::Error);
      }
      uploading_ = false;
    });
    return;
  }
  const RefParams r = ref_;
  if (const char* why = reference_check(r)) {
    ui_.message(std::string("not sent: ") + why, Role::Error);
    return;
  }
  worker_.post("selecting reference", [this, r] {
    try {
      console_.references().select(r);
      ui_.message(fmt::format("reference {} in force", reference_kind_name(r.kind)), Role::Ok);
    } catch (const std::exception& e) {
      ui_.message(e.what(), Role::Error);
    }
  });
}

bool RefPanel::key(int ch) {
  if (const int k = firmware_kind_.exchange(-1); k >= 0) select_kind(size_t(k));
  const auto ks = keys();
  if (edit_.active()) {
    if (edit_.key(ch) == LineEdit::Result::Done && selected_ < ks.size()) {
      const std::string& k = ks[selected_];
      try {
        if (!kKinds[kind_].preset) {
          if (k == "file") csv_path_ = edit_.text();
          else {
            RefParams tmp{};
            set_reference_key(tmp, console_.device().info().loop_rate_hz, "hold", edit_.text());
            csv_hold_ = tmp.hold;
          }
        } else {
          RefParams next = ref_;
          set_reference_key(next, console_.device().info().loop_rate_hz, k, edit_.text());
          ref_ = next;  // only a valid edit changes the working copy
        }
      } catch (const std::exception& e) {
        ui_.message(e.what(), Role::Error);
      }
    }
    return true;
  }
  if (move_cursor(ch, selected_, ks.size())) return true;
  switch (ch) {
    case KEY_LEFT:
    case 'h':
      kind_ = (kind_ + kKindCount - 1) % kKindCount;
      reset_kind();
      return true;
    case KEY_RIGHT:
    case 'l':
    case '\t':
      kind_ = (kind_ + 1) % kKindCount;
      reset_kind();
      return true;
    case '\n':
    case '\r':
    case KEY_ENTER:
      if (selected_ < ks.size()) {
        const std::string& k = ks[selected_];
        const std::string v = !kKinds[kind_].preset ? (k == "file" ? csv_path_ : std::to_string(csv_hold_))
                                                    : reference_key_value(ref_, console_.device().info().loop_rate_hz, k);
        edit_.start(k + " = ", v);
      }
      return true;
    case 'a':
      send();
      return true;
  }
  return false;
}

void RefPanel::draw(const Screen& screen, int y, int x, int h, int w, bool focused) {
  if (const int k = firmware_kind_.exchange(-1); k >= 0) select_kind(size_t(k));
  put(y, x, " Reference ", w, screen.attr(focused ? Role::Title : Role::KeyName));
  // The kinds wrap onto more rows in a narrow panel, so the one selected
  // is always on screen.
  int cx = x + 1, ky = y + 1;
  for (size_t i = 0; i < kKindCount; ++i) {
    const std::string label = fmt::format(" {} ", kKinds[i].label);
    if (cx > x + 1 && cx + int(label.size()) > x + w) cx = x + 1, ++ky;
    put(ky, cx, label, x + w - cx, i == kind_ ? screen.attr(Role::Selected) : 0);
    cx += int(label.size()) + 1;
  }
  const int top = ky + 2 - y;  // first row of the values
  const auto ks = keys();
  for (size_t i = 0; i < ks.size() && int(i) + top < h - 3; ++i) {
    const int ry = y + top + int(i);
    const bool sel = focused && i == selected_;
    fill_row(ry, x, w, sel ? screen.attr(Role::Selected) : 0);
    put(ry, x + 1, ks[i], 8, sel ? screen.attr(Role::Selected) : screen.attr(Role::KeyName));
    if (sel && edit_.active()) {
      edit_.draw(ry, x + 10, w - 11, screen.attr(Role::Selected), screen.ellipsis());
      continue;
    }
    std::string v = !kKinds[kind_].preset ? (ks[i] == "file" ? csv_path_ : std::to_string(csv_hold_))
                                          : reference_key_value(ref_, console_.device().info().loop_rate_hz, ks[i]);
    if (ks[i] == "period") v += " s";
    put(ry, x + 10, v, w - 11, sel ? screen.attr(Role::Selected) : 0);
  }
  if (uploading_) {
    const size_t t = up_total_.load(), d = up_done_.load();
    const int bw = std::max(10, w - 16);
    const int filled = t ? int(double(d) / double(t) * bw) : 0;
    put(y + h - 3, x + 1,
        fmt::format("upload [{}{}] {:3d}%", std::string(size_t(filled), '#'), std::string(size_t(bw - filled), '.'),
                    t ? int(100 * d / t) : 0),
        w - 2, screen.attr(Role::Pending));
  }
  const auto cur = console_.references().current();
  const int fw = firmware_ref_id_.load();
  put(y + h - 2, x + 1,
      elide_words(cur ? fmt::format("in force: {}", reference_kind_name(cur->kind))
                  : fw >= 0 && fw < int(kRefKindCount)
                      ? fmt::format("in force: {} (the firmware's own)", reference_kind_name(RefKind(fw)))
                      : "in force: firmware default",
                  size_t(std::max(0, w - 2)), screen.ellipsis()),
      w - 2, screen.attr(Role::Dim));
  if (edit_.active())
    put(y + h - 1, x + 1, edit_.hint(w - 2), w - 2, screen.attr(Role::Pending));
  else
    put(y + h - 1, x, fit_hints({"\u2190\u2192 kind", "Enter edit", "a send/upload"}, size_t(w), screen.ellipsis()), w,
        screen.attr(Role::Dim));
}

}  // namespace nlsoft::console::tui
