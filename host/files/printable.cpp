#include "host/files/printable.hpp"

#include <fmt/format.h>

namespace nlsoft::console {

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7f) {
      out += fmt::format("\\x{:02x}", c);
    } else if (c == 0xc2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
               static_cast<unsigned char>(text[i + 1]) <= 0x9f) {
      // U+0080..U+009F, the C1 controls: CSI (U+009B) starts an escape
      // sequence on terminals that take 8-bit controls.
      out += fmt::format("\\u{:04x}", static_cast<unsigned char>(text[i + 1]));
      ++i;
    } else {
      out += char(c);
    }
  }
  return out;
}

std::string printable_excerpt(std::string_view text, size_t max) {
  size_t chars = 0, cut = text.size();
  for (size_t i = 0; i < text.size(); ++i) {
    if ((static_cast<unsigned char>(text[i]) & 0xc0) == 0x80) continue;  // inside a UTF-8 sequence
    if (chars == max) {
      cut = i;
      break;
    }
    ++chars;
  }
  return printable(text.substr(0, cut)) + (cut < text.size() ? "…" : "");
}

}  // namespace nlsoft::console
