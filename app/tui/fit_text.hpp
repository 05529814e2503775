#pragma once
// Text shortened to the columns it has by rule, never mid-word (so never
// mid-number): a sentence loses its last words and ends in an ellipsis, a
// path its middle directories, a line of fields its least useful fields
// first. Widths are in columns (one per UTF-8 code point).
#include <string>
#include <vector>

namespace nlsoft::console::tui {

size_t text_columns(const std::string& s);

// The first `columns` columns of s (whole code points).
std::string first_columns(const std::string& s, size_t columns);

// s whole when it fits; else its words up to the last that fits (a comma
// parts words too: the items of a list or of JSON), the punctuation before
// the cut dropped, then `more` (an ellipsis); a path cut off keeps its
// file name (elide_path). A first word wider than the whole width is the
// one thing cut inside.
std::string elide_words(const std::string& s, size_t width, const std::string& more);

// A path whole when it fits; else its first directories and its file name
// with `more` for the directories between ("/tmp/nlsoft-…/runs.db"); when
// not even "…/name" fits, elide_words of it.
std::string elide_path(const std::string& path, size_t width, const std::string& more);

// Words of `text` in lines of at most `width` columns; a word wider than a
// line is split across lines.
std::vector<std::string> wrap_words(const std::string& text, size_t width);

// A line of fields joined by `sep`: while it is wider than `width` the
// field with the lowest `keep` goes (the first of equals); what is left
// still too wide is elided by words.
struct Field {
  std::string text;
  int keep;
};
std::string fit_fields(const std::vector<Field>& fields, const std::string& sep, size_t width,
                       const std::string& more);

// A panel's key hints ("Enter edit", "u undo", ...) joined by two blanks:
// all when they fit; else as many as fit, whole and in order, then `more`
// (the help, F1, lists every key). Never a hint cut inside.
std::string fit_hints(const std::vector<std::string>& hints, size_t width, const std::string& more);

// At most max_lines of `lines` (each at most `width` columns): when some
// are left out, the last kept one ends in `more`, cut by words.
std::vector<std::string> cut_lines(std::vector<std::string> lines, size_t max_lines, size_t width,
                                   const std::string& more);

}  // namespace nlsoft::console::tui
