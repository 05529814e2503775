#pragma once
// The reference the firmware follows: a kind and its values, or a table
// uploaded; and what a run that starts now follows, in the run's words.
// Separate because a run records it and the TUI's reference panel shows
// it, while only this console's own selections are known here.
#include <mutex>
#include <optional>
#include <string>

#include "app/link/device.hpp"
#include "app/live/active_run.hpp"
#include "app/live/board_rig.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

class LiveReferences {
 public:
  using Progress = std::function<void(size_t done, size_t total)>;

  LiveReferences(Device& device, const BoardRig& rig, ActiveRun& run) : device_(device), rig_(rig), run_(run) {}

  // Any thread that may talk to the device. Both log the change into the
  // active run.
  void select(const RefParams& ref);
  void upload_table(const std::string& csv_path, uint16_t hold, const Progress& progress = {});
  // What this console selected last; none before it selected any.
  std::optional<RefParams> current() const;
  // What a run starting now follows, as the run's `reference` JSON: this
  // console's selection, else the firmware's own choice named as such;
  // "" when that cannot be told.
  std::string run_json();

 private:
  // Kept for current() and run_json(), and logged into the active run.
  void remember(const RefParams& ref, const std::string& table_file);
  std::string firmware_reference_json();

  Device& device_;
  const BoardRig& rig_;
  ActiveRun& run_;
  mutable std::mutex mu_;
  std::optional<RefParams> reference_;
  std::string table_file_;
};

}  // namespace nlsoft::console
