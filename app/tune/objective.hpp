#pragma once
// The tuning objective: an arithmetic expression over run metrics,
// "nrmse + 0.1*u_effort", parsed once (every error before the first run)
// and evaluated on each evaluation's metrics.
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/record/run_metrics.hpp"

namespace nlsoft::console {

struct ObjectiveError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

class Objective {
 public:
  // Numbers, the metrics `expect` knows (metric_names(), rmse0..), + - * /,
  // unary minus and parentheses. Throws ObjectiveError naming the column.
  explicit Objective(const std::string& text);
  ~Objective();
  Objective(const Objective&);
  Objective& operator=(const Objective&);

  const std::string& text() const { return text_; }
  // The metrics it reads, in order of first use.
  const std::vector<std::string>& metrics() const { return metrics_; }
  // NaN when a metric it needs is not available (or is NaN itself): such
  // an evaluation cannot be scored.
  double operator()(const RunMetrics& m) const;

  struct Node;

 private:
  std::string text_;
  std::vector<std::string> metrics_;
  std::shared_ptr<const Node> root_;
};

}  // namespace nlsoft::console
