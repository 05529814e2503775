#pragma once
// The one error type of the model pipeline. Host-side code (never linked into
// firmware), so exceptions are fine here; the CLI turns each into a message
// and exit code 2.
#include <stdexcept>
#include <string>

namespace nlsoft::model {

struct PipelineError : std::runtime_error {
  explicit PipelineError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace nlsoft::model
