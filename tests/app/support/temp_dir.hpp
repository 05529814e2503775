#pragma once
// A scratch directory per test, removed afterwards.
#include <cstdlib>
#include <filesystem>
#include <string>

namespace nlsoft::test {

struct TempDir {
  TempDir() {
    char tmpl[] = "/tmp/nlsoft-console-test-XXXXXX";
    path = ::mkdtemp(tmpl);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return path + "/" + name; }
  std::string path;
};

}  // namespace nlsoft::test
