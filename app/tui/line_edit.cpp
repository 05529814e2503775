#include "app/tui/line_edit.hpp"

#include <algorithm>
#include <vector>

#include "app/tui/curses.hpp"
#include "app/tui/fit_text.hpp"
#include "app/tui/screen.hpp"

namespace nlsoft::console::tui {

void LineEdit::start(std::string prompt, std::string initial) {
  prompt_ = std::move(prompt);
  text_ = std::move(initial);
  cursor_ = text_.size();
  active_ = true;
  selected_ = !text_.empty();
  hist_pos_ = history_ ? history_->size() : 0;
}

LineEdit::Result LineEdit::key(int ch) {
  choices_.clear();
  if (selected_) {
    selected_ = false;
    const bool replaces = (ch >= 32 && ch < 127) || ch == KEY_BACKSPACE || ch == 127 || ch == 8 || ch == KEY_DC;
    if (replaces) {
      text_.clear();
      cursor_ = 0;
      if (ch < 32 || ch >= 127) return Result::Editing;  // the selection deleted, nothing typed
    }
  }
  switch (ch) {
    case '\t':
      if (completer_) {
        auto [done, choices] = completer_(text_.substr(0, cursor_));
        text_ = done + text_.substr(cursor_);
        cursor_ = done.size();
        for (const std::string& c : choices) choices_ += (choices_.empty() ? "" : " ") + c;
      }
      break;
    case '\n':
    case '\r':
    case KEY_ENTER:
      active_ = false;
      if (history_ && !text_.empty() && (history_->empty() || history_->back() != text_)) history_->push_back(text_);
      return Result::Done;
    case 27:  // Esc
      active_ = false;
      return Result::Cancelled;
    case KEY_LEFT:
      if (cursor_ > 0) --cursor_;
      break;
    case KEY_RIGHT:
      if (cursor_ < text_.size()) ++cursor_;
      break;
    case KEY_HOME:
    case 1:  // Ctrl-A
      cursor_ = 0;
      break;
    case KEY_END:
    case 5:  // Ctrl-E
      cursor_ = text_.size();
      break;
    case KEY_BACKSPACE:
    case 127:
    case 8:
      if (cursor_ > 0) text_.erase(--cursor_, 1);
      break;
    case KEY_DC:
      if (cursor_ < text_.size()) text_.erase(cursor_, 1);
      break;
    case 21:  // Ctrl-U
      text_.erase(0, cursor_);
      cursor_ = 0;
      break;
    case 23: {  // Ctrl-W
      size_t p = cursor_;
      while (p > 0 && text_[p - 1] == ' ') --p;
      while (p > 0 && text_[p - 1] != ' ') --p;
      text_.erase(p, cursor_ - p);
      cursor_ = p;
      break;
    }
    case KEY_UP:
      if (history_ && hist_pos_ > 0) text_ = (*history_)[--hist_pos_], cursor_ = text_.size();
      break;
    case KEY_DOWN:
      if (history_ && hist_pos_ < history_->size()) {
        ++hist_pos_;
        text_ = hist_pos_ < history_->size() ? (*history_)[hist_pos_] : "";
        cursor_ = text_.size();
      }
      break;
    default:
      if (ch >= 32 && ch < 127) text_.insert(cursor_++, 1, char(ch));
  }
  return Result::Editing;
}

void LineEdit::draw(int y, int x, int width, int attr, const char* more) const {
  fill_row(y, x, width, attr);
  const std::string all = prompt_ + text_ + (choices_.empty() ? "" : "   [" + choices_ + "]");
  const size_t cur = prompt_.size() + cursor_;
  // Scroll so the cursor stays in view, never starting inside a word of the
  // prompt: "= 1 1 1 1 1 1", not "bda = 1 1 1 1 1 1" (the panel's name
  // column names the parameter). Text scrolled out past the prompt is an
  // ellipsis in the first column.
  size_t first = cur >= size_t(width) ? cur - size_t(width) + 1 : 0;
  int lead = 0;  // columns the ellipsis takes
  if (first > 0 && first < prompt_.size() && prompt_[first - 1] != ' ') {
    const size_t blank = prompt_.find(' ', first);
    first = blank == std::string::npos ? prompt_.size() : blank + 1;
  } else if (first > prompt_.size() && width > 1) {
    lead = 1;
    first = cur - size_t(width - lead) + 1;
    put(y, x, more, 1, attr);
  }
  const int vx = x + lead, vw = width - lead;
  put(y, vx, all.substr(first), vw, attr);
  if (selected_ && prompt_.size() + text_.size() > first) {
    const size_t from = std::max(prompt_.size(), first);
    put(y, vx + int(from - first), text_.substr(from - prompt_.size()), vw - int(from - first), attr | A_UNDERLINE);
  }
  const int cx = vx + int(cur - first);
  if (cx < x + width) {
    attrset(attr | A_REVERSE);
    mvaddch(y, cx, cur < all.size() ? chtype(static_cast<unsigned char>(all[cur])) : ' ');
    attrset(A_NORMAL);
  }
}

std::string LineEdit::hint(int width) const {
  if (!active_) return "";
  // The longest that fits: the words, not a cut, carry the meaning.
  static const std::vector<std::string> selected = {
      "typing replaces the value; Left/Right/Home/End edit it; Esc cancels",
      "typing replaces it; Left/Right edit it; Esc cancels", "typing replaces it; Left/Right edit it",
      "type to replace, arrows edit", "typing replaces it"};
  static const std::vector<std::string> editing = {"Enter takes it; Esc cancels", "Enter takes it"};
  for (const std::string& h : selected_ ? selected : editing)
    if (int(text_columns(h)) <= width) return h;
  return "";
}

}  // namespace nlsoft::console::tui
