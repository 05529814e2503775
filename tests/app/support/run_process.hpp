#pragma once
// Runs a command through /bin/sh and captures stdout+stderr and the exit code.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace nlsoft::test {

struct ProcessResult {
  int code = -1;
  std::string output;
};

inline ProcessResult run_process(const std::string& command) {
  ProcessResult r;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int status = ::pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace nlsoft::test
