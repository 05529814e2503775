#pragma once
// The model pipeline's console subcommands: dataset, train, and
// model import|eval|info. Each reports bad input as an exception
// derived from std::runtime_error (main prints it, exit code 2) and writes
// its output atomically, so a failure leaves no half-written file.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_dataset_command(CLI::App& app);
void add_train_command(CLI::App& app);
void add_model_command(CLI::App& app);  // model import|eval|info

}  // namespace nlsoft::console
