#pragma once
// How well a trained model fits data it was not trained on, as system
// identification judges it: per output, the RMSE of one-step and of
// free-run prediction (fed its own outputs) over the held-out rows, as a
// fraction of the output's span. `train` prints it and keeps it in the
// model file (app/model/model_section.hpp); `model info` shows it.
#include <string>
#include <vector>

#include "app/model/plant_target.hpp"
#include "app/model/train.hpp"

namespace nlsoft::pipeline {

struct OutputFit {
  std::string name;
  double span = 0;      // the output's span, its unit
  double one_step = 0;  // nRMSE, a fraction of the span
  double free_run = 0;
};

struct ModelFit {
  std::string rig;       // the rig trained for
  std::string held_out;  // which rows, in words
  long rows = 0;
  std::vector<OutputFit> outputs;
};

ModelFit model_fit(const TrainResult& r, const PlantTarget& target);

// The table train prints and model info shows.
std::string fit_table(const ModelFit& f);

// The form kept in a model file: JSON text. fit_from_json throws
// PipelineError naming `where` for a text that is not one.
std::string fit_to_json(const ModelFit& f);
ModelFit fit_from_json(const std::string& text, const std::string& where);

}  // namespace nlsoft::pipeline
