#include "app/text/tokenize.hpp"

#include <stdexcept>

namespace nlsoft::console::text {

std::vector<std::string> tokenize(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool in_quotes = false, have = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (in_quotes) {
      if (c == '\\' && i + 1 < line.size() && line[i + 1] == '"') cur += line[++i];
      else if (c == '"') in_quotes = false;
      else cur += c;
    } else if (c == '#' && !have) {
      break;  // a comment to the end of the line
    } else if (c == '"') {
      in_quotes = have = true;
    } else if (c == ' ' || c == '\t') {
      if (have) out.push_back(cur), cur.clear(), have = false;
    } else {
      cur += c;
      have = true;
    }
  }
  if (in_quotes) throw std::invalid_argument("unterminated \"quote\"");
  if (have) out.push_back(cur);
  return out;
}

}  // namespace nlsoft::console::text
