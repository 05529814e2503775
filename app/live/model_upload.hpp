#pragma once
// A new forward model without a reflash (transfer kind 2). Separate
// because the file is checked here with the firmware's own parser, against
// the firmware's dimensions, platform, model shape (RIG_INFO) and transfer
// limit, before a byte is sent.
#include <cstdint>
#include <functional>
#include <string>

#include "app/link/device.hpp"
#include "app/live/active_run.hpp"

namespace nlsoft::console {

class ModelUpload {
 public:
  using Progress = std::function<void(size_t done, size_t total)>;
  struct Result {
    uint32_t previous_hash = 0, hash = 0;
    size_t bytes = 0;
    uint32_t params = 0, normalisation = 0;  // floats in the file, and how many of them normalise
  };

  ModelUpload(Device& device, const ActiveRun& run) : device_(device), run_(run) {}

  // Refused during a run (the firmware would refuse the commit). Afterwards
  // INFO is read again and the model hash it reports must be the file's
  // CRC-32. Throws CliError.
  Result send(const std::string& path, const Progress& progress = {});

 private:
  Device& device_;
  const ActiveRun& run_;
};

}  // namespace nlsoft::console
