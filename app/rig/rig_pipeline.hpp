#pragma once
// Any rig as the model pipeline sees it: the target `dataset` and `train`
// work on (dimensions, limits, history length, plant, layers).
#include <string>

#include "app/model/plant_target.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

model::PlantTarget rig_plant_target(const host::Rig& rig);

// `--rig ARG` / `--platform NAME` for dataset and train: load_rig_arg then
// rig_plant_target (a bad file or name: CliError, exit 2).
model::PlantTarget rig_target_arg(const std::string& arg);

}  // namespace nlsoft::console
