#include "app/model/model_fit.hpp"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "app/model/error.hpp"

namespace nlsoft::pipeline {

ModelFit model_fit(const TrainResult& r, const PlantTarget& target) {
  ModelFit f;
  f.rig = target.name;
  f.held_out = r.held_out;
  f.rows = r.test.rows;
  for (size_t j = 0; j < r.test.mse.size(); ++j) {
    OutputFit o;
    o.name = j < target.y_names.size() ? target.y_names[j] : "y" + std::to_string(j);
    o.span = j < target.y_span.size() ? target.y_span[j] : 0.0;
    const double scale = o.span > 0 ? 1.0 / o.span : 1.0;
    o.one_step = std::sqrt(r.test.mse[j]) * scale;
    o.free_run = std::sqrt(r.test.free_run_mse[j]) * scale;
    f.outputs.push_back(o);
  }
  return f;
}

std::string fit_table(const ModelFit& f) {
  std::string out = "fit on held-out data of rig " + f.rig + ": " + f.held_out + "\n";
  char line[160];
  std::snprintf(line, sizeof line, "  %-12s %10s %16s %16s\n", "output", "span", "one-step nRMSE", "free-run nRMSE");
  out += line;
  for (const OutputFit& o : f.outputs) {
    std::snprintf(line, sizeof line, "  %-12s %10.4g %14.3g %% %14.3g %%\n", o.name.c_str(), o.span,
                  100.0 * o.one_step, 100.0 * o.free_run);
    out += line;
  }
  return out;
}

std::string fit_to_json(const ModelFit& f) {
  nlohmann::json j;
  j["rig"] = f.rig;
  j["held_out"] = f.held_out;
  j["rows"] = f.rows;
  j["outputs"] = nlohmann::json::array();
  for (const OutputFit& o : f.outputs)
    j["outputs"].push_back({{"name", o.name}, {"span", o.span}, {"one_step_nrmse", o.one_step},
                            {"free_run_nrmse", o.free_run}});
  return j.dump();
}

ModelFit fit_from_json(const std::string& text, const std::string& where) {
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    ModelFit f;
    f.rig = j.at("rig").get<std::string>();
    f.held_out = j.at("held_out").get<std::string>();
    f.rows = j.at("rows").get<long>();
    for (const auto& o : j.at("outputs"))
      f.outputs.push_back({o.at("name").get<std::string>(), o.at("span").get<double>(),
                           o.at("one_step_nrmse").get<double>(), o.at("free_run_nrmse").get<double>()});
    return f;
  } catch (const nlohmann::json::exception& e) {
    throw PipelineError(where + ": its fit section is not readable: " + e.what());
  }
}

}  // namespace nlsoft::pipeline
