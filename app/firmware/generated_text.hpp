#pragma once
// User text (a file name, a path) as the generated sources write it: one
// escaping function per target language, so that whatever bytes the text
// holds it stays data there and reads back byte for byte.
#include <optional>
#include <string>

namespace nlsoft::console {

// A C++ string literal: quote, backslash and '?' (no trigraph) escaped, every
// byte outside printable ASCII as an octal escape, so a newline, a `*/` or
// a `#` inside cannot end the literal, the line or a comment around it.
std::string cpp_string_literal(const std::string& text);

// A CMake bracket argument ([==[...]==]) with enough '=' that the text
// cannot close it; CMake expands nothing inside one.
std::string cmake_bracket(const std::string& text);

// The value `set(NAME <bracket argument>)` gives NAME in a generated
// image.cmake, or nothing when the file has no such line.
std::optional<std::string> cmake_bracket_value(const std::string& cmake, const std::string& name);

}  // namespace nlsoft::console
