#include "app/firmware/generated_text.hpp"

#include <fmt/format.h>

namespace nlsoft::console {

std::string cpp_string_literal(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\' || c == '?') {
      out += '\\';
      out += c;
    } else if (byte < 0x20 || byte > 0x7e) {
      // Three digits always: a digit after the escape cannot extend it.
      out += fmt::format("\\{:03o}", byte);
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string cmake_bracket(const std::string& text) {
  std::string equals;
  while (text.find("]" + equals + "]") != std::string::npos) equals += '=';
  // CMake drops one newline right after the opening bracket: give it one of
  // its own, so a text that starts with a newline keeps it.
  return "[" + equals + "[\n" + text + "]" + equals + "]";
}

std::optional<std::string> cmake_bracket_value(const std::string& cmake, const std::string& name) {
  const std::string tag = "set(" + name + " [";
  const size_t at = cmake.find(tag);
  if (at == std::string::npos) return std::nullopt;
  size_t p = at + tag.size();
  std::string equals;
  while (p < cmake.size() && cmake[p] == '=') equals += '=', ++p;
  if (cmake.compare(p, 2, "[\n") != 0) return std::nullopt;
  p += 2;
  const size_t end = cmake.find("]" + equals + "]", p);
  if (end == std::string::npos) return std::nullopt;
  return cmake.substr(p, end - p);
}

}  // namespace nlsoft::console
