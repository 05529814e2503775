#pragma once
// Loads model files into the host-capacity Model, and finds the default
// model of a platform.
#include <string>
#include <vector>

#include "shared/model.hpp"
#include "shared/platform_id.hpp"

namespace nlsoft::console {

struct LoadedModel {
  Model<HostCapacity> model;
  std::vector<float> storage;  // model.params points here
  std::vector<uint8_t> file;   // the raw file, for upload
  std::string path;
  int platform = 255;          // as recorded in the file
  LoadedModel() = default;
  LoadedModel(const LoadedModel&) = delete;
  LoadedModel& operator=(const LoadedModel&) = delete;
};

// Throws CliError with the file name and the reason on any failure.
void load_model(const std::string& path, LoadedModel& out);

}  // namespace nlsoft::console
