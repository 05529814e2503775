#pragma once
// A one-line editor for the `:` prompt and in-place edits: arrows, Home/End,
// Backspace/Delete, Ctrl-U (clear), Ctrl-W (word), history with Up/Down,
// Tab completion when given a completer. A value it opens with (an edit in
// place, a file name offered) is taken as selected, as editors do: the first
// character typed replaces it, Backspace/Delete/Ctrl-U clear it, and an
// arrow, Home or End keeps it to be edited; hint() says so meanwhile.
#include <functional>
#include <string>
#include <vector>

namespace nlsoft::console::tui {

class LineEdit {
 public:
  enum class Result { Editing, Done, Cancelled };

  void start(std::string prompt, std::string initial = "");
  Result key(int ch);
  bool active() const { return active_; }
  bool selected() const { return active_ && selected_; }  // the opening value still selected
  const std::string& text() const { return text_; }
  const std::string& prompt() const { return prompt_; }
  // Draws prompt + text on row y, cursor visible; the opening value, while
  // it is selected, underlined. Text scrolled out at the left is shown as
  // `more` (Screen::ellipsis()).
  void draw(int y, int x, int width, int attr, const char* more = "~") const;
  // What the keys do now, in at most `width` columns ("" when nothing fits
  // or nothing is to be said): while the opening value is selected, that
  // typing replaces it; afterwards, how the edit ends.
  std::string hint(int width) const;
  void set_history(std::vector<std::string>* h) { history_ = h; }
  // Tab: given the text left of the cursor, returns it completed and, when
  // the word is still ambiguous, the choices (shown after the text).
  using Completer = std::function<std::pair<std::string, std::vector<std::string>>(const std::string&)>;
  void set_completer(Completer c) { completer_ = std::move(c); }

 private:
  std::string prompt_, text_;
  size_t cursor_ = 0;
  bool active_ = false;
  bool selected_ = false;  // the opening value, until the first key
  std::vector<std::string>* history_ = nullptr;
  size_t hist_pos_ = 0;
  Completer completer_;
  std::string choices_;  // after an ambiguous Tab, until the next key
};

}  // namespace nlsoft::console::tui
