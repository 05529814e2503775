#include "host/files/printable.hpp"

#include <fmt/format.h>

#include <cstdint>

namespace nlsoft::host {

namespace {

// The length of the well-formed UTF-8 sequence at text[i] and its code
// point, or 0 when the bytes there are not one (a stray continuation byte
// such as a raw 0x9b, an overlong form, a surrogate, a cut sequence).
size_t utf8_at(std::string_view text, size_t i, uint32_t& cp) {
  const auto b = [&](size_t k) { return static_cast<unsigned char>(text[i + k]); };
  const unsigned char c = b(0);
  size_t len = 0;
  uint32_t min = 0;
  if (c >= 0xc2 && c <= 0xdf) len = 2, cp = c & 0x1f, min = 0x80;
  else if (c >= 0xe0 && c <= 0xef) len = 3, cp = c & 0x0f, min = 0x800;
  else if (c >= 0xf0 && c <= 0xf4) len = 4, cp = c & 0x07, min = 0x10000;
  else return 0;
  if (i + len > text.size()) return 0;
  for (size_t k = 1; k < len; ++k) {
    if ((b(k) & 0xc0) != 0x80) return 0;
    cp = (cp << 6) | (b(k) & 0x3f);
  }
  if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return 0;
  return len;
}

// Code points a terminal acts on or that reorder what is shown: the C1
// controls (U+009B is CSI on terminals that take 8-bit controls) and the
// bidirectional overrides and isolates, which make a line read otherwise
// than its bytes.
bool is_control_point(uint32_t cp) {
  return (cp >= 0x80 && cp <= 0x9f) || (cp >= 0x202a && cp <= 0x202e) || (cp >= 0x2066 && cp <= 0x2069);
}

}  // namespace

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
    } else if (c < 0x80) {
      out += char(c);
    } else {
      uint32_t cp = 0;
      const size_t len = utf8_at(text, i, cp);
      if (len == 0) {
        // Not UTF-8 (a raw 0x9b among them): each byte as its value.
        out += fmt::format("\\x{:02x}", c);
      } else {
        if (is_control_point(cp)) out += fmt::format("\\u{:04x}", cp);
        else out.append(text.substr(i, len));
        i += len - 1;
      }
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

std::string printable_within(std::string_view text, size_t max_bytes) {
  std::string out = printable(text);
  if (out.size() <= max_bytes) return out;
  static constexpr std::string_view kCut = "…";
  if (max_bytes < kCut.size()) return std::string(max_bytes, '.');
  // printable's output is ASCII but for whole, printable UTF-8 sequences:
  // back up to the start of one so that none is cut in two.
  size_t end = max_bytes - kCut.size();
  while (end > 0 && (static_cast<unsigned char>(out[end]) & 0xc0) == 0x80) --end;
  out.resize(end);
  return out += kCut;
}

void printable_into(const char* raw, char* out, size_t capacity) {
  if (capacity == 0) return;
  const std::string safe = printable_within(raw, capacity - 1);
  safe.copy(out, safe.size());
  out[safe.size()] = '\0';
}

}  // namespace nlsoft::host
