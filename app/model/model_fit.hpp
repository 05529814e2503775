#pragma once
// How well a trained model fits data it was not trained on, as system
// identification judges it (app/model/fit_scores.hpp): per output, RMSE,
// nRMSE of the output's span and fit % of one-step and free-run prediction,
// the network's beside a linear ARX baseline's on the same lags
// (app/model/arx.hpp). `train` prints it and keeps it in the model file
// with the baseline (app/model/model_section.hpp); `model info` shows it;
// `model fit` measures the same on any run.
#include <string>
#include <vector>

#include "app/model/arx.hpp"
#include "app/model/fit_scores.hpp"
#include "app/model/plant_target.hpp"
#include "app/model/train.hpp"

namespace nlsoft::model {

struct OutputFit {
  std::string name;
  double span = 0;                   // the output's span, its unit
  Score one_step, free_run;          // the network
  Score arx_one_step, arx_free_run;  // the ARX baseline (when the section has one)
  Score k_step, arx_k_step;          // at the section's horizon (when it has one)
};

// The fit on one stretch of data.
struct FitSection {
  std::string title;  // what was fitted, in words: "held-out data of rig msd: run 2, whole (997 rows)"
  long rows = 0;
  bool has_arx = false;
  // > 1: also scored k steps ahead, the controller's horizon N (fit_scores.hpp).
  int horizon = 0;
  std::vector<OutputFit> outputs;
};

struct ModelFit {
  std::string rig;       // the rig trained for
  std::string held_out;  // the first section's rows, in words
  std::string unit;      // the outputs' unit ("" normalised)
  // [0] the held-out data; with --validate-run then the training runs'
  // validation fold, reported apart.
  std::vector<FitSection> sections;
  std::string arx;  // the baseline, arx_to_json; empty: none (a fit of an older console)
  std::string lags;  // how nd = dd was chosen, in words (app/model/lag_search.hpp); empty: not said
};

// Scores the network, and `arx` unless null, on rows `pieces` of d.
FitSection fit_section(const std::string& title, const ModelFile& model, const ArxModel* arx, const Dataset& d,
                       const std::vector<RowRange>& pieces, const PlantTarget& target, int horizon = 0);

ModelFit model_fit(const TrainResult& r, const PlantTarget& target);

// The tables train prints, model info shows and model fit prints per run.
std::string fit_table(const ModelFit& f);
std::string section_table(const FitSection& s, const std::string& unit);

// A line for train to print when the fit's ARX column (double) is far
// better than the kept model while ARX in float, a candidate, was not; empty
// when there is nothing to explain.
std::string float_gap_words(const TrainResult& r, const ModelFit& fit, const std::string& unit);

// The form kept in a model file: JSON text. fit_from_json throws
// PipelineError naming `where` for a text that is not one; it reads the
// fits of older consoles too (nRMSE only, no baseline).
std::string fit_to_json(const ModelFit& f);
ModelFit fit_from_json(const std::string& text, const std::string& where);
// One section as JSON (model fit --json).
std::string section_to_json(const FitSection& s, const std::string& unit);

}  // namespace nlsoft::model
