#pragma once
// `runs plot`: a picture of one run, or two overlaid. Per output axis y_ref,
// y_hat and y_true against time; u per actuator; the path in the plane of
// the first two axes (the x-y projection of a Swirl); the run's parameters
// in the caption. Drawn by gnuplot (app/record/gnuplot.hpp); this file only
// writes its script, so what is drawn can be tested without gnuplot.
#include <cstdint>
#include <string>
#include <vector>

#include "app/record/run_metrics.hpp"
#include "app/record/run_store.hpp"
#include "app/simulate/simulation_picture.hpp"

namespace nlsoft::console {

struct PlottedRun {
  RunRow row;
  RunSeries series;
  RunMetrics metrics;
  std::vector<ParamRecord> params;
  // Axis names with their units ("x (mm)") from the run's rig file; where
  // the rig is not known, y0, u0, l0.
  std::vector<std::string> output_labels, input_labels, sensor_labels;
};

enum class ImageFormat { Svg, Png };

// Reads a run for plotting; throws CliError for an unknown id or a run
// without samples.
PlottedRun load_plotted_run(RunStore& store, int64_t id);

// The gnuplot script that draws `runs` (one or two) to standard output in
// that format. Long runs are thinned to at most max_points rows each.
std::string run_plot_script(const std::vector<PlottedRun>& runs, ImageFormat format, size_t max_points = 4000);

// `simulate --svg/--png`: the simulation drawn as a run, named by its label
// ("simulate infinity on lab-arm") where a run has its id.
std::string simulation_plot_script(const SimulationPicture& p, size_t max_points = 4000);

}  // namespace nlsoft::console
