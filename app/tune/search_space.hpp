#pragma once
// What `tune` may change: parameters of the firmware's table, each over a
// range, searched on a unit cube so the optimiser sees every dimension
// alike (a :log range is uniform in its logarithm: Q from 1e5 to 1e7 is as
// far from 1e6 one way as the other).
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "app/link/param_catalog.hpp"

namespace nlsoft::console {

// The parameters a search's names are resolved against and its start read
// from: the connected firmware's table (live_param_source.hpp), or the
// simulator a replay runs in this process (replay_evaluator.hpp).
class ParamSource {
 public:
  virtual ~ParamSource() = default;
  // "Q" -> (Q, -1); "Q[1]", "Q1" -> (Q, 1). Throws CliError in words.
  virtual std::pair<ParamInfo, int> resolve(const std::string& name) = 0;
  // The values in force now.
  virtual std::vector<double> in_force(const ParamInfo& info) = 0;
};

// One searched dimension, as written: NAME=LO..HI[:log|:lin].
//   Lambda=0.01..100:log   every element of Lambda, one value
//   Q1=1e5..1e7:log        one element (also Q[1])
//   Q*=0.1..1e3:log        a common factor on Q as it was at the start:
//                          the weights keep their proportions
struct Dimension {
  std::string spec, name;
  double lo = 0, hi = 0;
  bool log = false;
};

// Syntax only (the names are checked against the firmware later). Throws
// std::invalid_argument in words.
Dimension parse_dimension(const std::string& spec);

class SearchSpace {
 public:
  using Write = std::pair<ParamInfo, std::vector<double>>;

  // Resolves the dimensions against the firmware's parameter list and the
  // values in force: known names, elements that exist, ranges inside each
  // parameter's own range, no parameter given twice. Throws CliError.
  SearchSpace(ParamSource& params, std::vector<Dimension> dims);

  size_t size() const { return dims_.size(); }
  const std::vector<Dimension>& dimensions() const { return dims_; }
  // The values in force at the start, on the unit cube (clamped into the
  // ranges; clamped() names the ones that were outside).
  std::vector<double> start() const;
  const std::vector<std::string>& clamped() const { return clamped_; }
  // A coordinate in [0, 1] to the dimension's value (integer parameters are
  // rounded).
  double value(size_t d, double unit) const;
  // The parameter writes that put a point in force, one per parameter, in
  // the order the parameters were first named.
  std::vector<Write> writes(const std::vector<double>& unit) const;
  // The parameters touched, as they were before tuning.
  const std::vector<Write>& original() const { return original_; }
  // "Lambda=0.52 Q*=12.3"
  std::string describe(const std::vector<double>& unit) const;
  // "Lambda=0.01..100:log Q*=0.1..1000:log"
  std::string text() const;

 private:
  struct Target {
    size_t param;      // index into original_
    int element = -1;  // -1: every element
    bool scale = false;
  };
  std::vector<Dimension> dims_;
  std::vector<Target> targets_;
  std::vector<Write> original_;
  std::vector<std::string> clamped_;
};

}  // namespace nlsoft::console
