#pragma once
// A line split into words as a user types them: script lines (and the TUI's
// ':' line), tune's search-space text.
#include <string>
#include <vector>

namespace nlsoft::console::text {

// Splits on blanks; "double quotes" group, \" escapes a quote, and a '#'
// that starts a word ends the line (a comment). Throws std::invalid_argument
// for an unterminated quote.
std::vector<std::string> tokenize(const std::string& line);

}  // namespace nlsoft::console::text
