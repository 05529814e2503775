#pragma once
// Test support: runs the model subcommands through the test driver
// (model_cli_main.cpp) as a user would, returning the exit code and output.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "support/text_checks.hpp"

namespace nlsoft::test {

struct CliResult {
  int code;
  std::string output;  // stdout and stderr together
};

inline CliResult run_cli(const std::string& args) {
  // one log per process and call: ctest runs test cases in parallel
  static int calls = 0;
  const std::string log =
      ::testing::TempDir() + "/cli_output_" + std::to_string(::getpid()) + "_" + std::to_string(++calls) + ".txt";
  const std::string cmd = std::string(NLSOFT_MODEL_CLI) + " " + args + " > " + log + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::string output = nlsoft::test::slurp(log);
  std::remove(log.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

inline bool file_exists(const std::string& path) { return std::ifstream(path).good(); }

}  // namespace nlsoft::test
