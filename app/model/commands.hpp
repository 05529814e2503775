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

// `--rig ARG` (`--platform` its synonym) goes through `resolve`; without
// one, only the compiled-in platforms' names are known
// (pipeline::platform_target_by_name).
void add_dataset_command(CLI::App& app, pipeline::TargetResolver resolve = {});
// `train --run ID` reads runs through `load_run` (the console's database,
// app/record/run_training.hpp); without one --run is refused.
void add_train_command(CLI::App& app, pipeline::TargetResolver resolve = {}, pipeline::RunLoader load_run = {});
// model import|eval|info|fit; `model fit` resolves rigs, reads runs and
// draws through these (each empty: the pipeline's own, none, none).
void add_model_command(CLI::App& app, pipeline::TargetResolver resolve = {}, pipeline::RunLoader load_run = {},
                       ScriptPlotter plot = {});

}  // namespace nlsoft::console
