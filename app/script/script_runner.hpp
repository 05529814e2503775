#pragma once
// Executes parsed script commands against a connected console. The same
// runner serves `--script FILE` (exit codes for CI) and the TUI's `:` line.
#include <functional>
#include <string>

#include "app/live/live_console.hpp"
#include "app/script/script_parser.hpp"

namespace nlsoft::console {

class ScriptRunner {
 public:
  using Output = std::function<void(const std::string& line)>;
  using Progress = std::function<void(const std::string& what, size_t done, size_t total)>;

  ScriptRunner(LiveConsole& console, Output out, Progress progress = {})
      : console_(console), out_(std::move(out)), progress_(std::move(progress)) {}

  // Runs every command in order. Returns 0 when every expect held, 1 when
  // one failed, 2 on a script or link error (the message names file:line;
  // an active run is stopped first).
  int run(const Script& script);

  // One command; throws ScriptError (file:line: ...) on failure. A failed
  // expect is not an exception: it is reported and counted.
  void execute(const Command& c, const std::string& file);

  int failed_expects() const { return failed_; }
  int passed_expects() const { return passed_; }

 private:
  void sweep(const Command& c);
  LiveConsole& console_;
  Output out_;
  Progress progress_;
  int failed_ = 0, passed_ = 0;
};

}  // namespace nlsoft::console
