#pragma once
// Parameters by name, one element or whole, and parameter files: saved,
// loaded all or nothing, compared with and reset to the rig's defaults.
// Separate because it keeps this session's edits, which a firmware reset
// (FirmwareResets) names and sends again.
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "app/link/device.hpp"
#include "app/live/active_run.hpp"
#include "app/live/board_rig.hpp"

namespace nlsoft::console {

class LiveParams {
 public:
  using Edits = std::vector<std::pair<ParamInfo, std::vector<double>>>;

  LiveParams(Device& device, const BoardRig& rig, ActiveRun& run) : device_(device), rig_(rig), run_(run) {}

  // Any thread that may talk to the device (the TUI's worker, a script).
  // "Q[1]" addresses one element, the rest keep their value. Returns the
  // echoed value in force. Logs the change into the run.
  std::vector<double> set(const std::string& name, const std::vector<std::string>& values);
  std::pair<ParamInfo, std::vector<double>> get(const std::string& name);
  // Sends a whole value and logs the change into the active run.
  std::vector<double> apply(const ParamInfo& info, const std::vector<double>& values);
  // "Q" -> (Q, -1); "Q[1]" and "Q1" -> (Q, 1). Throws CliError naming the
  // known parameters, or the valid element range.
  std::pair<ParamInfo, int> resolve(const std::string& name) const;

  // Returns the lines of the diff; applies nothing if dry_run. On a refusal
  // rolls back what was applied and throws.
  std::vector<std::string> load(const std::string& path, bool dry_run = false);
  void save(const std::string& path);
  // Against the values the firmware boots with (param_defaults.hpp): every
  // parameter that differs, "Q: 2e+06 2e+06 1e+06 (default 1e+06 2e+06 1e+06)";
  // and all of them put back, all or nothing, returning what changed.
  std::vector<std::string> diff_from_defaults();
  std::vector<std::string> reset_to_defaults();

  // This session's edits as echoed, oldest first, one per name.
  Edits edits() const;

 private:
  struct WantedValue {
    ParamInfo info;  // a copy: the catalog may be reread meanwhile
    std::vector<double> values;
    std::string origin;  // "file:line" or "default", for a refusal's message
  };
  // Sends every value that differs from the one in force, all or nothing
  // (a refusal puts back what went through); returns "name: from -> to".
  std::vector<std::string> apply_values(const std::vector<WantedValue>& wanted, bool dry_run);
  std::vector<WantedValue> defaults_wanted() const;

  Device& device_;
  const BoardRig& rig_;
  ActiveRun& run_;
  mutable std::mutex mu_;
  Edits edits_;
};

// Element by element as the firmware holds them (float).
bool same_param_values(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace nlsoft::console
