#pragma once
// Rig-file texts in tests: edit one, find a line, and expect the loader's
// exact "file:line: label: what" for it. The files are named my.toml.
#include <gtest/gtest.h>

#include <string>

#include "host/rig/rig.hpp"

namespace nlsoft::host::rig_text {

// The 1-based line of the n-th (1-based) occurrence of `needle` in `text`.
inline int line_of(const std::string& text, const std::string& needle, int nth = 1) {
  size_t at = std::string::npos, from = 0;
  for (int i = 0; i < nth; ++i) {
    at = text.find(needle, from);
    if (at == std::string::npos) return -1;
    from = at + 1;
  }
  int line = 1;
  for (size_t i = 0; i < at; ++i) line += text[i] == '\n';
  return line;
}

// `text` with the nth occurrence of `from` replaced by `to`.
inline std::string replaced(std::string text, const std::string& from, const std::string& to, int nth = 1) {
  size_t at = std::string::npos, pos = 0;
  for (int i = 0; i < nth; ++i) {
    at = text.find(from, pos);
    pos = at + 1;
  }
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The error parse_rig throws for `text`, or an empty one if it loads.
inline RigError error_of(const std::string& text) {
  try {
    parse_rig(text, "my.toml");
  } catch (const RigError& e) {
    return e;
  }
  return RigError("", "", 0, "");
}

// The message is exactly "my.toml:<line>: <label>: <what...>".
inline void expect_error(const std::string& text, int line, const std::string& label, const std::string& what) {
  const RigError e = error_of(text);
  const std::string head = "my.toml:" + std::to_string(line) + ": " + label + ": ";
  EXPECT_EQ(std::string(e.what()).substr(0, head.size()), head) << e.what();
  EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  EXPECT_EQ(e.file, "my.toml");
  EXPECT_EQ(e.line, line) << e.what();
}

}  // namespace nlsoft::host::rig_text
