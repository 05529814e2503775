#pragma once
// What `simulate --svg/--png` hands to the drawing (the recorder's
// `runs plot`, app/record/run_plot.hpp): the simulated trace, what it was
// and how well it tracked. Its own header so that the simulator does not
// depend on the recorder.
#include <functional>
#include <string>
#include <vector>

#include "app/metrics/tracking_metrics.hpp"
#include "app/simulate/closed_loop.hpp"

namespace nlsoft::console {

struct SimulationPicture {
  const Trace* trace = nullptr;
  std::string rig, reference;
  TrackingMetrics truth, predicted;
  bool svg = true;  // else PNG
  // The rig's output and input names with units ("x (mm)"), for the axes.
  std::vector<std::string> output_labels, input_labels;
};

// The image's bytes; empty in a build without the recorder.
using SimulationPlotter = std::function<std::string(const SimulationPicture&)>;

}  // namespace nlsoft::console
