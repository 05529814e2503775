#pragma once
// `model fit MODEL (--run ID ... | --data FILE.csv ...)`: the model judged
// on recorded runs or files as system identification judges it (free run
// and one-step, RMSE, nRMSE and fit % per output), beside its ARX baseline
// (kept by train, or refitted from --train-run), as a table per run, JSON,
// and a picture drawn with gnuplot.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "app/model/plant_target.hpp"
#include "app/model/recorded_run.hpp"

namespace nlsoft::console {

// Draws a gnuplot script and returns the image (the console's run_gnuplot,
// app/record/gnuplot.hpp); empty: --svg/--png are refused.
using ScriptPlotter = std::function<std::string(const std::string& script)>;

void add_model_fit_command(CLI::App& model_command, model::TargetResolver resolve, model::PlatformNamer name_platform,
                           model::RunLoader load_run, ScriptPlotter plot);

}  // namespace nlsoft::console
