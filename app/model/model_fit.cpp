#include "app/model/model_fit.hpp"

#include <cmath>
#include <cstdio>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/model/error.hpp"

namespace nlsoft::model {
namespace {

nlohmann::json score_json(const Score& s) {
  // JSON has no NaN: an undefined fit (a constant output) is null.
  return {{"rmse", s.rmse}, {"nrmse", s.nrmse},
          {"fit_percent", std::isfinite(s.fit) ? nlohmann::json(s.fit) : nlohmann::json(nullptr)}};
}

Score score_from(const nlohmann::json& j) {
  Score s;
  s.rmse = j.at("rmse").get<double>();
  s.nrmse = j.at("nrmse").get<double>();
  s.fit = j.at("fit_percent").is_null() ? std::nan("") : j.at("fit_percent").get<double>();
  return s;
}

nlohmann::json section_json(const FitSection& s) {
  nlohmann::json j;
  j["title"] = s.title;
  j["rows"] = s.rows;
  j["outputs"] = nlohmann::json::array();
  for (const OutputFit& o : s.outputs) {
    // one_step_nrmse, free_run_nrmse: what consoles before the baseline read.
    nlohmann::json e = {{"name", o.name},
                        {"span", o.span},
                        {"one_step_nrmse", o.one_step.nrmse},
                        {"free_run_nrmse", o.free_run.nrmse},
                        {"one_step", score_json(o.one_step)},
                        {"free_run", score_json(o.free_run)}};
    if (s.has_arx) e["arx"] = {{"one_step", score_json(o.arx_one_step)}, {"free_run", score_json(o.arx_free_run)}};
    if (s.horizon > 1) {
      e["k_step"] = score_json(o.k_step);
      if (s.has_arx) e["arx"]["k_step"] = score_json(o.arx_k_step);
    }
    j["outputs"].push_back(e);
  }
  if (s.horizon > 1) j["horizon"] = s.horizon;
  return j;
}

FitSection section_from(const nlohmann::json& j, const std::string& title) {
  FitSection s;
  s.title = title;
  s.rows = j.at("rows").get<long>();
  s.has_arx = !j.at("outputs").empty();
  s.horizon = j.contains("horizon") ? j.at("horizon").get<int>() : 0;
  for (const auto& o : j.at("outputs")) {
    OutputFit f;
    f.name = o.at("name").get<std::string>();
    if (s.horizon > 1) f.k_step = score_from(o.at("k_step"));
    f.span = o.at("span").get<double>();
    if (o.contains("one_step")) {
      f.one_step = score_from(o.at("one_step"));
      f.free_run = score_from(o.at("free_run"));
    } else {  // an older console's: nRMSE only
      f.one_step.nrmse = o.at("one_step_nrmse").get<double>();
      f.free_run.nrmse = o.at("free_run_nrmse").get<double>();
      f.one_step.rmse = f.one_step.nrmse * (f.span > 0 ? f.span : 1.0);
      f.free_run.rmse = f.free_run.nrmse * (f.span > 0 ? f.span : 1.0);
      f.one_step.fit = f.free_run.fit = std::nan("");
    }
    if (o.contains("arx")) {
      f.arx_one_step = score_from(o.at("arx").at("one_step"));
      f.arx_free_run = score_from(o.at("arx").at("free_run"));
      if (s.horizon > 1) f.arx_k_step = score_from(o.at("arx").at("k_step"));
    } else {
      s.has_arx = false;
    }
    s.outputs.push_back(f);
  }
  return s;
}

std::string cell(const char* fmt, double v) {
  char buf[48];
  if (!std::isfinite(v)) return "-";
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

}  // namespace

FitSection fit_section(const std::string& title, const ModelFile& model, const ArxModel* arx, const Dataset& d,
                       const std::vector<RowRange>& pieces, const PlantTarget& target, int horizon) {
  FitSection s;
  s.title = title;
  s.horizon = horizon > 1 ? horizon : 0;
  const Eigen::MatrixXd y = measured(d, pieces);
  s.rows = long(y.rows());
  const Simulation net = simulate_network(model, d, pieces, s.horizon);
  const std::vector<Score> one = score(y, net.one_step, target.y_span), free = score(y, net.free_run, target.y_span);
  const std::vector<Score> ahead = s.horizon ? score(y, net.k_step, target.y_span) : std::vector<Score>{};
  std::vector<Score> arx_one, arx_free, arx_ahead;
  if (arx) {
    const Simulation a = simulate_arx(*arx, d, pieces, s.horizon);
    arx_one = score(y, a.one_step, target.y_span);
    arx_free = score(y, a.free_run, target.y_span);
    if (s.horizon) arx_ahead = score(y, a.k_step, target.y_span);
    s.has_arx = true;
  }
  for (int j = 0; j < d.layout.n; ++j) {
    OutputFit o;
    o.name = size_t(j) < target.y_names.size() ? target.y_names[size_t(j)] : "y" + std::to_string(j);
    o.span = size_t(j) < target.y_span.size() ? target.y_span[size_t(j)] : 0.0;
    o.one_step = one[size_t(j)];
    o.free_run = free[size_t(j)];
    if (s.horizon) o.k_step = ahead[size_t(j)];
    if (arx) {
      o.arx_one_step = arx_one[size_t(j)];
      o.arx_free_run = arx_free[size_t(j)];
      if (s.horizon) o.arx_k_step = arx_ahead[size_t(j)];
    }
    s.outputs.push_back(o);
  }
  return s;
}

ModelFit model_fit(const TrainResult& r, const PlantTarget& target) {
  ModelFit f;
  f.rig = target.name;
  f.held_out = r.held_out;
  f.unit = target.y_unit;
  const ArxModel* arx = r.arx.theta.size() > 0 ? &r.arx : nullptr;
  if (arx) f.arx = arx_to_json(r.arx);
  f.sections.push_back(
      fit_section("held-out data of rig " + target.name + ": " + r.held_out, r.model, arx, r.data, r.test_pieces, target));
  if (!r.val_pieces.empty() && r.validate_run)
    f.sections.push_back(fit_section("the training runs' validation part (the last 1/" + std::to_string(r.folds + 1) +
                                         " of each, not trained on)",
                                     r.model, arx, r.data, r.val_pieces, target));
  return f;
}

std::string section_table(const FitSection& s, const std::string& unit) {
  std::string out = "fit on " + s.title + "\n";
  char line[256];
  std::snprintf(line, sizeof line, "  %-10s %11s  %-9s %13s %11s %8s", "output", "span", "predicts", "network RMSE",
                "nRMSE", "fit %");
  out += line;
  if (s.has_arx) {
    std::snprintf(line, sizeof line, "  %13s %11s %8s", "ARX RMSE", "nRMSE", "fit %");
    out += line;
  }
  out += "\n";
  const std::string u = unit.empty() ? "" : " " + unit;
  for (const OutputFit& o : s.outputs) {
    const std::pair<const Score*, const Score*> rows[] = {
        {&o.one_step, &o.arx_one_step}, {&o.k_step, &o.arx_k_step}, {&o.free_run, &o.arx_free_run}};
    const std::string ahead = std::to_string(s.horizon) + "-step";
    const char* names[] = {"one-step", ahead.c_str(), "free-run"};
    for (int k = 0; k < 3; ++k) {
      if (k == 1 && s.horizon <= 1) continue;
      const Score& n = *rows[k].first;
      std::snprintf(line, sizeof line, "  %-10s %11s  %-9s %13s %11s %8s", o.name.c_str(), (cell("%.4g", o.span) + u).c_str(),
                    names[k], (cell("%.4g", n.rmse) + u).c_str(), (cell("%#.3g", 100.0 * n.nrmse) + " %").c_str(),
                    cell("%.2f", n.fit).c_str());
      out += line;
      if (s.has_arx) {
        const Score& a = *rows[k].second;
        std::snprintf(line, sizeof line, "  %13s %11s %8s", (cell("%.4g", a.rmse) + u).c_str(),
                      (cell("%#.3g", 100.0 * a.nrmse) + " %").c_str(), cell("%.2f", a.fit).c_str());
        out += line;
      }
      out += "\n";
    }
  }
  return out;
}

std::string fit_table(const ModelFit& f) {
  // The history length first: the tables below end at their last row.
  std::string out = f.lags.empty() ? std::string() : "history: " + f.lags + "\n";
  for (const FitSection& s : f.sections) out += section_table(s, f.unit);
  if (f.arx.empty()) out += "(no ARX baseline kept with this fit)\n";
  return out;
}

std::string section_to_json(const FitSection& s, const std::string& unit) {
  nlohmann::json j = section_json(s);
  for (auto& o : j["outputs"]) o.erase("one_step_nrmse"), o.erase("free_run_nrmse");  // the file's compatibility keys
  j["unit"] = unit;
  return j.dump();
}

std::string fit_to_json(const ModelFit& f) {
  nlohmann::json j;
  j["rig"] = f.rig;
  j["unit"] = f.unit;
  // The first section's rows at the top as before, for consoles that read only those.
  j["held_out"] = f.held_out;
  j["rows"] = f.sections.empty() ? 0L : f.sections[0].rows;
  j["outputs"] = f.sections.empty() ? nlohmann::json::array() : section_json(f.sections[0])["outputs"];
  j["sections"] = nlohmann::json::array();
  for (const FitSection& s : f.sections) j["sections"].push_back(section_json(s));
  if (!f.arx.empty()) j["arx"] = nlohmann::json::parse(f.arx);
  if (!f.lags.empty()) j["lags"] = f.lags;
  return j.dump();
}

ModelFit fit_from_json(const std::string& text, const std::string& where) {
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    ModelFit f;
    f.rig = j.at("rig").get<std::string>();
    f.held_out = j.at("held_out").get<std::string>();
    if (j.contains("unit")) f.unit = j.at("unit").get<std::string>();
    if (j.contains("sections")) {
      for (const auto& s : j.at("sections")) f.sections.push_back(section_from(s, s.at("title").get<std::string>()));
    } else {
      f.sections.push_back(section_from(j, "held-out data of rig " + f.rig + ": " + f.held_out));
    }
    if (j.contains("arx")) f.arx = j.at("arx").dump();
    if (j.contains("lags")) f.lags = j.at("lags").get<std::string>();
    return f;
  } catch (const nlohmann::json::exception& e) {
    throw PipelineError(where + ": its fit section is not readable: " + e.what());
  }
}

// The fit table's ARX column is the textbook baseline, simulated in double;
// the candidates were all judged as the firmware runs a model, in float.
// Where the double ARX is far better than the kept model, the same least
// squares in float is not (it was a candidate): say so, or a user reads the
// table as train keeping a worse model (msd's 1 kHz identification run:
// ARX 7.1e-07 m in double, 0.024 m in float with the ridge float needs, the kept model 0.00031 m).
std::string float_gap_words(const TrainResult& r, const ModelFit& fit, const std::string& unit) {
  if (r.objective != Objective::Simulation || fit.sections.empty() || !fit.sections[0].has_arx) return "";
  const Candidate* arx = nullptr;
  for (const Candidate& c : r.candidates)
    if (c.arx) arx = &c;
  if (!arx || r.candidates.empty()) return "";
  const Candidate& kept = r.candidates[r.chosen];
  const std::string u = unit.empty() ? "" : " " + unit;
  std::string words;
  for (size_t j = 0; j < fit.sections[0].outputs.size() && j < arx->held_out_rmse.size() &&
                     j < kept.held_out_rmse.size();
       ++j) {
    const OutputFit& o = fit.sections[0].outputs[j];
    if (!(o.arx_free_run.rmse * 2.0 < kept.held_out_rmse[j])) continue;
    // Below a hundred-thousandth of the span both are rounding: nothing to explain.
    if (o.span > 0 && kept.held_out_rmse[j] < 1e-5 * o.span) continue;
    words += fmt::format("{}{}: ARX {:.4g}{} in double, {:.4g}{} in float, the kept model {:.4g}{}",
                         words.empty() ? "" : "; ", o.name, o.arx_free_run.rmse, u, arx->held_out_rmse[j], u,
                         kept.held_out_rmse[j], u);
  }
  if (words.empty()) return "";
  return "the ARX column is least squares simulated in double; the firmware runs every model in float, and so were "
         "the candidates judged: " + words + " (free run of the held-out rows). The gap is float rounding, not a "
         "better model left behind.";
}

}  // namespace nlsoft::model
