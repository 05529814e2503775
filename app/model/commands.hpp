#pragma once
// The model pipeline's console subcommands: dataset, train, and
// model import|eval|info. Each reports bad input as an exception
// derived from std::runtime_error (main prints it, exit code 2) and writes
// its output atomically, so a failure leaves no half-written file.
#include <CLI/CLI.hpp>

#include "app/model/fit_command.hpp"
#include "app/model/plant_target.hpp"
#include "app/model/recorded_run.hpp"

namespace nlsoft::console {

// `--rig ARG` (`--platform` its deprecated synonym) goes through `resolve`
// (the console's: app/rig/rig_pipeline.hpp rig_target_arg).
void add_dataset_command(CLI::App& app, model::TargetResolver resolve);
// `train --run ID` reads runs through `load_run` (the console's database,
// app/record/run_training.hpp); without one --run is refused.
void add_train_command(CLI::App& app, model::TargetResolver resolve, model::RunLoader load_run = {});
// model import|eval|info|fit: rigs resolved through `resolve`, a model
// file's platform number named through `name_platform`; `model fit` reads
// runs and draws through the last two (each empty: none).
void add_model_command(CLI::App& app, model::TargetResolver resolve, model::PlatformNamer name_platform,
                       model::RunLoader load_run = {}, ScriptPlotter plot = {});

}  // namespace nlsoft::console
