#include "app/tui/fit_text.hpp"

#include <algorithm>

namespace nlsoft::console::tui {

namespace {

size_t code_point_length(unsigned char c) { return c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : 4; }

// The byte offset where column `columns` of s starts (s.size() past its end).
size_t byte_at_column(const std::string& s, size_t columns) {
  size_t at = 0;
  for (size_t c = 0; c < columns && at < s.size(); ++c) at += code_point_length(static_cast<unsigned char>(s[at]));
  return std::min(at, s.size());
}

std::string join(const std::vector<Field>& fields, const std::string& sep) {
  std::string out;
  for (const Field& f : fields) out += (out.empty() ? "" : sep) + f.text;
  return out;
}

}  // namespace

size_t text_columns(const std::string& s) {
  size_t n = 0;
  for (size_t at = 0; at < s.size(); at += code_point_length(static_cast<unsigned char>(s[at]))) ++n;
  return n;
}

std::string first_columns(const std::string& s, size_t columns) { return s.substr(0, byte_at_column(s, columns)); }

std::string elide_words(const std::string& s, size_t width, const std::string& more) {
  if (text_columns(s) <= width) return s;
  const size_t room = width > text_columns(more) ? width - text_columns(more) : 0;
  std::string head = first_columns(s, room);
  // Cut where a word ends: at the last space inside the room, or right
  // after it when the next character starts a new word.
  const size_t next = head.size();
  if (next < s.size() && std::string(" ,;:").find(s[next]) == std::string::npos) {
    // A comma parts the items of a word without blanks too (a list, JSON).
    const size_t space = head.find_last_of(" ,");
    if (space != std::string::npos && head.find_first_not_of(' ') < space) head.resize(space);
  }
  while (!head.empty() && std::string(" ,;:|=(").find(head.back()) != std::string::npos) head.pop_back();
  // The word cut off is a path: its middle goes rather than all of it
  // ("recording to /tmp/…/runs.db").
  const size_t from = s.find_first_not_of(' ', head.size());
  if (from != std::string::npos && from > 0 && s[from - 1] == ' ') {
    const size_t to = std::min(s.find(' ', from), s.size());
    const std::string word = s.substr(from, to - from);
    const size_t used = text_columns(head) + 1, rest = width > used ? width - used : 0;
    const bool last = to == s.size();
    const size_t fits = last ? rest : rest > text_columns(more) ? rest - text_columns(more) : 0;
    if (word.find('/') != std::string::npos && word.find('/') < word.size() - 1 && fits >= 12) {
      const std::string path = elide_path(word, fits, more);
      if (path.find('/') != std::string::npos && text_columns(path) <= fits)
        return head + " " + path + (last ? "" : more);
    }
  }
  return head + more;
}

std::string elide_path(const std::string& path, size_t width, const std::string& more) {
  if (text_columns(path) <= width) return path;
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos || slash == 0) return elide_words(path, width, more);
  const std::string name = path.substr(slash);  // "/runs.db"
  const size_t tail = text_columns(more) + text_columns(name);
  if (tail > width) return elide_words(path, width, more);
  return first_columns(path.substr(0, slash), width - tail) + more + name;
}

std::vector<std::string> wrap_words(const std::string& text, size_t width) {
  std::vector<std::string> lines;
  if (width == 0) return lines;
  std::string line, word;
  auto flush_word = [&] {
    while (text_columns(word) > width) {  // a word wider than a line: split, after a '/' or '-' if it has one
      if (!line.empty()) lines.push_back(line), line.clear();
      std::string piece = first_columns(word, width);
      const size_t sep = piece.find_last_of("/-");
      if (sep != std::string::npos && sep > 0) piece.resize(sep + 1);
      lines.push_back(piece);
      word.erase(0, piece.size());
    }
    if (word.empty()) return;
    if (!line.empty() && text_columns(line) + 1 + text_columns(word) > width) lines.push_back(line), line.clear();
    line += (line.empty() ? "" : " ") + word;
    word.clear();
  };
  for (char c : text) {
    if (c == ' ') flush_word();
    else word += c;
  }
  flush_word();
  if (!line.empty()) lines.push_back(line);
  return lines;
}

std::string fit_fields(const std::vector<Field>& fields, const std::string& sep, size_t width,
                       const std::string& more) {
  std::vector<Field> left = fields;
  while (left.size() > 1 && text_columns(join(left, sep)) > width)
    left.erase(std::min_element(left.begin(), left.end(), [](const Field& a, const Field& b) { return a.keep < b.keep; }));
  return elide_words(join(left, sep), width, more);
}

std::string fit_hints(const std::vector<std::string>& hints, size_t width, const std::string& more) {
  std::string all;
  for (const std::string& h : hints) all += (all.empty() ? "" : "  ") + h;
  if (text_columns(all) <= width) return all;
  const size_t tail = text_columns(more) + 1;  // " …"
  std::string out;
  for (const std::string& h : hints) {
    const std::string next = out + (out.empty() ? "" : "  ") + h;
    if (text_columns(next) + tail > width) break;
    out = next;
  }
  if (out.empty()) return text_columns(more) <= width ? more : "";
  return out + " " + more;
}

std::vector<std::string> cut_lines(std::vector<std::string> lines, size_t max_lines, size_t width,
                                   const std::string& more) {
  if (lines.size() <= max_lines) return lines;
  if (max_lines == 0) return {};
  // The last kept line and the next together are too wide: elide_words
  // cuts them at a word and ends them in `more`.
  lines[max_lines - 1] = elide_words(lines[max_lines - 1] + " " + lines[max_lines] + " " + more, width, more);
  lines.resize(max_lines);
  return lines;
}

}  // namespace nlsoft::console::tui
