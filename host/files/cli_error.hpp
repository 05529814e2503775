#pragma once
// A user-facing error: main() prints the message and exits with the code
// (2 for bad input or a failed link, as the scripts contract says).
#include <stdexcept>
#include <string>

namespace nlsoft::host {

struct CliError : std::runtime_error {
  explicit CliError(const std::string& what, int code = 2) : std::runtime_error(what), exit_code(code) {}
  int exit_code;
};

}  // namespace nlsoft::host

namespace nlsoft::host {

// Thrown by a subcommand's callback to end the program with a status code
// once CLI11 has finished parsing.
struct CliExit {
  int code;
};

}  // namespace nlsoft::host
