#include "app/tui/list_cursor.hpp"
#include "app/tui/param_panel.hpp"

#include <fmt/format.h>

#include "host/files/cli_error.hpp"
#include "app/link/link_error.hpp"
#include "app/live/param_text.hpp"
#include "app/tui/curses.hpp"
#include "app/tui/fit_text.hpp"

namespace nlsoft::console::tui {

using host::CliError;

void ParamPanel::reload() { fetch(false); }
void ParamPanel::reload_after_reset() { fetch(true); }

void ParamPanel::fetch(bool after_reset) {
  worker_.post("reading parameters", [this, after_reset] {
    try {
      const auto all = console_.device().get_all();
      std::lock_guard<std::mutex> lock(mu_);
      std::vector<Row> rows;
      for (const auto& [info, v] : all) {
        Row r;
        r.info = info;
        r.value = v;
        for (const Row& old : rows_) {
          if (old.info.name != info.name) continue;
          // Keep what the user saw happen to each row across a reload.
          if (old.state == State::Refused || old.state == State::Reset) r.state = old.state, r.note = old.note;
          bool same = old.value.size() == v.size();
          for (size_t i = 0; same && i < v.size(); ++i) same = float(old.value[i]) == float(v[i]);
          if (after_reset && !same) {
            r.state = State::Reset;
            r.note = "reset, was " + format_param_values(old.info, old.value);
          } else if (after_reset && r.state == State::Applied) {
            r.state = State::Idle;
          }
        }
        rows.push_back(std::move(r));
      }
      rows_ = std::move(rows);
      loading_error_.clear();
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lock(mu_);
      loading_error_ = e.what();
    }
  });
}

void ParamPanel::send(size_t row, const std::vector<double>& values, bool record_undo) {
  ParamInfo info;
  std::vector<double> before;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (row >= rows_.size()) return;
    rows_[row].state = State::Pending;
    rows_[row].note = format_param_values(rows_[row].info, values);
    info = rows_[row].info;
    before = rows_[row].value;
  }
  worker_.post("setting " + info.name, [this, row, values, record_undo, info, before] {
    State state;
    std::string note;
    std::vector<double> now = before;
    try {
      now = console_.params().apply(info, values);
      state = State::Applied;
      bool same = true;
      for (size_t i = 0; i < now.size() && i < values.size(); ++i) same &= float(now[i]) == float(values[i]);
      note = same ? "applied" : "applied as " + format_param_values(info, now);
    } catch (const LinkError& e) {
      state = State::Unconfirmed;
      note = std::string("not confirmed, R rereads: ") + e.what();
    } catch (const std::exception& e) {
      state = State::Refused;
      note = e.what();
    }
    std::lock_guard<std::mutex> lock(mu_);
    if (row >= rows_.size()) return;
    rows_[row].value = now;
    rows_[row].state = state;
    rows_[row].note = note;
    if (state == State::Applied && record_undo) undo_.emplace_back(row, before);
    ui_.message(fmt::format("{}: {}", info.name, note),
                state == State::Applied ? Role::Ok : state == State::Unconfirmed ? Role::Warn : Role::Error);
  });
}

void ParamPanel::reapply() {
  worker_.post("re-applying this session's edits", [this] {
    try {
      const auto sent = console_.resets().reapply();
      ui_.message(sent.empty() ? "no edits in this session to send again"
                               : fmt::format("{} edit{} sent again", sent.size(), sent.size() == 1 ? "" : "s"),
                  Role::Ok);
      {
        std::lock_guard<std::mutex> lock(mu_);
        for (Row& r : rows_)
          if (r.state == State::Reset) r.state = State::Idle, r.note.clear();
      }
    } catch (const std::exception& e) {
      ui_.message(e.what(), Role::Error);
    }
  });
  reload();
}

void ParamPanel::save() {
  ui_.prompt("save parameters to: ", "params.txt", [this](const std::string& path) {
    if (path.empty()) return;
    worker_.post("saving parameters", [this, path] {
      try {
        console_.params().save(path);
        ui_.message("parameters saved to " + path, Role::Ok);
      } catch (const std::exception& e) {
        ui_.message(e.what(), Role::Error);
      }
    });
  });
}

void ParamPanel::load() {
  ui_.prompt("load parameters from: ", "params.txt", [this](const std::string& path) {
    if (path.empty()) return;
    worker_.post("reading " + path, [this, path] {
      try {
        const auto diff = console_.params().load(path, true);
        if (diff.empty()) {
          ui_.message(path + ": every parameter already has that value", Role::Ok);
          return;
        }
        ui_.confirm("send these changes from " + path + "?", diff, [this, path] {
          worker_.post("loading " + path, [this, path] {
            try {
              const auto applied = console_.params().load(path);
              ui_.message(fmt::format("{}: {} parameter{} changed", path, applied.size(), applied.size() == 1 ? "" : "s"),
                          Role::Ok);
            } catch (const std::exception& e) {
              ui_.message(e.what(), Role::Error);
            }
          });
          reload();
        });
      } catch (const std::exception& e) {
        ui_.message(e.what(), Role::Error);
      }
    });
  });
}

bool ParamPanel::key(int ch) {
  if (edit_.active()) {
    const auto r = edit_.key(ch);
    if (r == LineEdit::Result::Done) {
      std::vector<std::string> tokens;
      std::string t;
      for (char c : edit_.text() + " ") {
        if (c == ' ' || c == ',') {
          if (!t.empty()) tokens.push_back(t), t.clear();
        } else {
          t += c;
        }
      }
      ParamInfo info;
      {
        std::lock_guard<std::mutex> lock(mu_);
        if (selected_ >= rows_.size()) return true;
        info = rows_[selected_].info;
      }
      try {
        send(selected_, parse_param_values(info, expand_param_tokens(info, tokens)), true);
      } catch (const CliError& e) {
        std::lock_guard<std::mutex> lock(mu_);
        rows_[selected_].state = State::Refused;
        rows_[selected_].note = e.what();
        ui_.message(e.what(), Role::Error);
      }
    }
    return true;
  }
  // unique_lock: 'u' releases it while send() takes it itself.
  std::unique_lock<std::mutex> lock(mu_);
  const size_t n = rows_.size();
  if (move_cursor(ch, selected_, n)) return true;
  switch (ch) {
    case '\n':
    case '\r':
    case KEY_ENTER:
      if (selected_ < n) {
        const Row& r = rows_[selected_];
        if (r.info.read_only()) {
          ui_.message(r.info.name + " is read-only", Role::Warn);
        } else {
          edit_.start(r.info.name + " = ", format_param_values(r.info, r.value));
        }
      }
      return true;
    case 'u':
      if (undo_.empty()) {
        ui_.message("nothing to undo", Role::Warn);
      } else {
        const auto [row, value] = undo_.back();
        undo_.pop_back();
        lock.unlock();
        send(row, value, false);
        lock.lock();
      }
      return true;
    case 'S':
      save();
      return true;
    case 'L':
      load();
      return true;
    case 'R':
      reload();
      return true;
    case 'A':
      lock.unlock();
      reapply();
      lock.lock();
      return true;
  }
  return false;
}

void ParamPanel::draw_details(const Screen& screen, const Row& r, int y, int x, int h, int w) {
  const size_t width = size_t(std::max(1, w - 2)), room = size_t(std::max(0, h - 1));
  const std::string what = param_description(r.info.name);
  std::vector<std::string> about =
      wrap_words(r.info.name + ": " + (what.empty() ? "(no description for this parameter)" : what), width);
  const std::vector<std::string> range = wrap_words(param_range_text(r.info), width);
  std::vector<std::string> note;
  const bool noted = r.state == State::Refused || r.state == State::Unconfirmed || r.state == State::Reset;
  if (noted) note = wrap_words((r.state == State::Refused ? "refused: " : "") + r.note, width);
  // Too many lines for the room: the description gives way first (the
  // range and a refusal say what to type), ending in an ellipsis where cut,
  // never mid-sentence without one.
  const size_t others = range.size() + note.size();
  about = cut_lines(about, room > others ? room - others : std::min<size_t>(1, room), width, screen.ellipsis());
  std::vector<std::pair<std::string, Role>> lines;
  for (const auto& l : about) lines.emplace_back(l, Role::Normal);
  std::vector<std::string> tail = range;
  for (const auto& l : note) tail.push_back(l);
  tail = cut_lines(tail, room > about.size() ? room - about.size() : 0, width, screen.ellipsis());
  for (size_t i = 0; i < tail.size(); ++i)
    lines.emplace_back(tail[i], i < range.size() ? Role::Dim : r.state == State::Refused ? Role::Error : Role::Warn);
  attrset(screen.attr(Role::Border));
  mvhline(y, x, screen.utf8() ? ACS_HLINE : '-', w);
  attrset(A_NORMAL);
  for (int i = 0; i + 1 < h && size_t(i) < lines.size(); ++i)
    put(y + 1 + i, x + 1, lines[size_t(i)].first, w - 2, screen.attr(lines[size_t(i)].second));
}

void ParamPanel::draw(const Screen& screen, int y, int x, int h, int w, bool focused) {
  std::lock_guard<std::mutex> lock(mu_);
  put(y, x, fmt::format(" Parameters ({}) ", rows_.size()), w, screen.attr(focused ? Role::Title : Role::KeyName));
  if (!loading_error_.empty()) put(y + 1, x, loading_error_, w, screen.attr(Role::Error));
  if (rows_.empty()) {
    put(y + 2, x + 1, "reading the firmware's parameter list...", w - 2, screen.attr(Role::Dim));
    return;
  }
  // The selected row's details take the lines above the hint when there is
  // room for them and a few rows of the list.
  const int details = h >= 14 ? 6 : 0;
  const int body = h - 3 - details;  // title, hint line, one spare for the edit
  if (body <= 0) return;
  if (selected_ < top_) top_ = selected_;
  if (selected_ >= top_ + size_t(body)) top_ = selected_ - size_t(body) + 1;
  // A narrow panel (an 80-column terminal) abbreviates the long names; the
  // details below the list and the edit line give the whole name.
  const bool narrow = w < 36;
  const int name_w = narrow ? 8 : 12;
  const char* more = screen.ellipsis();
  for (int i = 0; i < body && top_ + size_t(i) < rows_.size(); ++i) {
    const size_t idx = top_ + size_t(i);
    const Row& r = rows_[idx];
    const int ry = y + 1 + i;
    const bool sel = focused && idx == selected_;
    fill_row(ry, x, w, sel ? screen.attr(Role::Selected) : 0);
    const std::string name =
        int(r.info.name.size()) < name_w ? r.info.name : r.info.name.substr(0, size_t(name_w - 2)) + more;
    put(ry, x + 1, name, name_w, sel ? screen.attr(Role::Selected) : screen.attr(Role::KeyName));
    if (sel && edit_.active()) {
      edit_.draw(ry, x + 1 + name_w, w - 2 - name_w, screen.attr(Role::Selected), screen.ellipsis());
      continue;
    }
    std::string value = format_param_named(r.info, r.value);
    if (!r.info.unit.empty()) value += " " + r.info.unit;
    std::string mark;
    Role role = Role::Normal;
    switch (r.state) {
      case State::Idle: break;
      case State::Pending: mark = " pending " + r.note; role = Role::Pending; break;
      case State::Applied: mark = " " + r.note; role = Role::Ok; break;
      case State::Refused: mark = " refused: " + r.note; role = Role::Error; break;
      case State::Unconfirmed: mark = " not confirmed (no reply)"; role = Role::Warn; break;
      case State::Reset: mark = " " + r.note; role = Role::Warn; break;
    }
    const int vw = std::max(0, w - 2 - name_w);
    value = elide_words(value, size_t(vw), more);
    put(ry, x + 1 + name_w, value, vw, sel ? screen.attr(Role::Selected) : 0);
    const int used = std::min(vw, int(text_columns(value)));
    if (!mark.empty() && vw - used > 1)
      put(ry, x + 1 + name_w + used, elide_words(mark, size_t(vw - used), more), vw - used, screen.attr(role));
  }
  if (details > 0 && selected_ < rows_.size()) draw_details(screen, rows_[selected_], y + h - 1 - details, x, details, w);
  if (edit_.active())  // what the keys do to the value being edited, in place of the panel's keys
    put(y + h - 1, x + 1, edit_.hint(w - 2), w - 2, screen.attr(Role::Pending));
  else
    put(y + h - 1, x,
        narrow ? fit_hints({"Enter u S L R A (F1)"}, size_t(w), screen.ellipsis())
               : fit_hints({"Enter edit", "u undo", "S/L save/load", "R reread", "A reapply"}, size_t(w),
                           screen.ellipsis()),
        w, screen.attr(Role::Dim));
}

}  // namespace nlsoft::console::tui
