#pragma once
// What `dataset` and `train` need to know of a rig: its dimensions, input
// limits, the plant that stands in for it and the network's shape. The
// pipeline does not read rig files; the console builds a target from one
// (app/rig/rig_pipeline.hpp) and hands the commands that resolver.
#include <functional>
#include <string>
#include <vector>

#include "app/model/network.hpp"
#include "shared/plant_generic.hpp"
#include "shared/plant_registry.hpp"

namespace nlsoft::model {

enum class TargetPlant { None, Named, Generic };

struct PlantTarget {
  std::string name;  // the rig's name, in messages
  int m = 0, n = 0, w = 0, nd = 2, dd = 2;
  bool lags_auto = false;          // the rig file leaves nd, dd to train's search (nd = dd: its longest)
  double rate_hz = 0;              // the control rate (0: not known)
  int horizon = 1;                 // the controller's prediction horizon N: the least a model is trained to simulate
  std::vector<double> u_lo, u_hi;  // the inputs' limits
  std::vector<double> y_rest;      // each output with every input at neutral: where train centres the outputs
  std::vector<double> y_span;      // each output's task-space span: what a fit's nRMSE is relative to
  std::vector<std::string> y_names;  // each output's name, in the fit's table
  std::string y_unit;              // the first output's unit ("" normalised)
  // The simulated stand-in: a hand-written plant (its own excitation time
  // scales and training defaults), a generic one, or none (data from the
  // rig itself; train centres the outputs on y_rest).
  TargetPlant plant = TargetPlant::None;
  PlantKind kind = PlantKind::Generic;    // TargetPlant::Named: the hand-written plant
  uint8_t platform = 255;                 // the model file's platform number (INFO's), 255: none
  GenericPlantSpec generic{};             // TargetPlant::Generic
  std::vector<LayerSpec> layers;          // the rig's [model] layers; empty: the defaults
  // The controller feeds back the measured output (else its own
  // predictions): what the network must be trained for.
  bool measured_feedback = false;
};

// Resolves `--rig ARG` (or `--platform NAME`) to a target; throws an
// exception derived from std::runtime_error with the reason (exit 2).
using TargetResolver = std::function<PlantTarget(const std::string& arg)>;

// The shipped rig a model file's platform number names (INFO's, the rig
// file's info_platform); empty when no shipped rig has that number.
using PlatformNamer = std::function<std::string(uint8_t platform)>;

}  // namespace nlsoft::model
