#include "app/gnuplot_text.hpp"

namespace nlsoft::console {

std::string gnuplot_string(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\n') out += "'.\"\\n\".'";
    else if (c == '\r') out += "'.\"\\r\".'";
    else if (c == '\'') out += "''";
    else out += c;
  }
  return out + "'";
}

}  // namespace nlsoft::console
