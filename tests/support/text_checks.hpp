#pragma once
// What the tests ask of a text: whether it holds a phrase, and a
// file's whole contents. One definition for every test file (a unity build
// merges them into one source).
#include <fstream>
#include <sstream>
#include <string>

namespace nlsoft::test {

inline bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

// The file's bytes as they are (empty when it cannot be read).
inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace nlsoft::test
