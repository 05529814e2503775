#include "app/model/fit_command.hpp"

#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/model/error.hpp"
#include "app/model/fit_plot.hpp"
#include "app/model/model_fit.hpp"
#include "host/files/output_file.hpp"
#include "host/rig/rig_option.hpp"

namespace nlsoft::console {

using host::OutputFile;
using host::OutputTarget;
using host::add_rig_option;
using host::output_target;

namespace {

using namespace nlsoft::model;

struct FitArgs {
  std::string model, rig, db, svg, png;
  std::vector<int64_t> runs, train_runs;
  std::vector<std::string> data;
  bool json = false;
  int horizon = -1;  // < 0: each run's controller horizon N
};

// The image's path, checked before any work so a bad one costs nothing and
// writes nothing: output_file's rules (a directory, a loop of links are
// refused), and a device too: an image is a file (or "-", /dev/stdout).
void check_image_path(const std::string& path) {
  const OutputTarget t = output_target(path);
  struct stat st {};
  if (t.kind == OutputTarget::InPlace && ::stat(t.path.c_str(), &st) == 0 && (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)))
    throw PipelineError("cannot write " + path + ": it is a device; give a file for the image (or '-')");
}

// Every run's rows stacked as one dataset, pieces kept apart: what the
// baseline is refitted on from --train-run.
Dataset stack(const std::vector<Dataset>& sets) {
  Dataset d;
  d.layout = sets.front().layout;
  long rows = 0;
  for (const Dataset& s : sets) rows += s.rows();
  d.X.resize(rows, d.layout.p());
  d.Y.resize(rows, d.layout.n);
  long at = 0;
  for (const Dataset& s : sets) {
    copy_rows(d, at, s, 0, s.rows());
    at += s.rows();
  }
  return d;
}

RecordedRun read_run(const RunLoader& loader, const std::string& db, int64_t id) {
  if (!loader) throw PipelineError("--run needs the console's database, which this build lacks");
  return loader(db, id);
}

// The rig the model is judged for: --rig, else the one train recorded,
// else the model's platform; refused when the model was not made for it.
PlantTarget fit_target(const FitArgs& a, const ModelFile& f, const ModelFit& stored, bool has_fit,
                       const TargetResolver& resolve, const PlatformNamer& name_platform) {
  const Model<HostCapacity> M = f.view();
  std::string rig = a.rig;
  if (rig.empty()) rig = stored.rig;
  if (rig.empty()) rig = name_platform(f.platform);
  if (rig.empty()) throw PipelineError(a.model + " names no rig (no fit kept with it): give --rig");
  PlantTarget target;
  try {
    target = resolve(rig);
  } catch (const std::exception& e) {
    if (!a.rig.empty()) throw;
    // The name train recorded: a rig file's needs its path.
    throw PipelineError(a.model + " was trained for rig '" + rig + "', which is no rig known by name (" + e.what() +
                        "): give --rig with its rig file");
  }
  if (has_fit && stored.rig != target.name)
    throw PipelineError(a.model + " was trained for rig '" + stored.rig + "', not for rig '" + target.name +
                        "': a model learnt on one rig does not describe another");
  if (M.m != target.m || M.n != target.n || M.w != target.w)
    throw PipelineError(a.model + " has m=" + std::to_string(M.m) + " n=" + std::to_string(M.n) + " w=" +
                        std::to_string(M.w) + " but rig '" + target.name + "' has m=" + std::to_string(target.m) +
                        " n=" + std::to_string(target.n) + " w=" + std::to_string(target.w));
  return target;
}

// The data the model is judged on, and per series how many steps ahead it
// is scored too (0, 1: not).
struct Judged {
  std::vector<Series> series;
  std::vector<int> horizons;
};

Judged judged_data(const FitArgs& a, const PlantTarget& target, const RunLoader& load_run) {
  Judged j;
  for (int64_t id : a.runs) {
    const RecordedRun run = read_run(load_run, a.db, id);
    j.series.push_back(recorded_series(run, target));
    j.horizons.push_back(a.horizon >= 0 ? a.horizon : run.horizon);
  }
  for (const std::string& file : a.data) {
    j.series.push_back(read_training_csv(file, target));
    check_dimensions(j.series.back(), target);
    j.horizons.push_back(std::max(a.horizon, 0));
  }
  return j;
}

// The ARX baseline: refitted on --train-run's runs, else the one train
// kept; none (theta empty) otherwise. `from` says which.
ArxModel baseline_arx(const FitArgs& a, const PlantTarget& target, const Model<HostCapacity>& M,
                      const ModelFit& stored, const RunLoader& load_run, std::string& from) {
  from = "none";
  if (!a.train_runs.empty()) {
    std::vector<Dataset> sets;
    std::string names;
    for (int64_t id : a.train_runs) {
      sets.push_back(build_dataset(recorded_series(read_run(load_run, a.db, id), target), M.nd, M.dd));
      names += (names.empty() ? "run " : ", run ") + std::to_string(id);
    }
    const Dataset d = stack(sets);
    from = "refitted on " + names;
    return fit_arx(d, d.pieces);
  }
  if (!stored.arx.empty()) {
    from = "kept by train";
    return arx_from_json(stored.arx, a.model);
  }
  return ArxModel{};
}

// Each series scored (and, for a picture, simulated) by the model and the baseline.
std::vector<FittedRun> fit_runs(const FitArgs& a, const ModelFile& f, const PlantTarget& target, const Judged& judged,
                                const ArxModel* baseline, bool drawn) {
  const Model<HostCapacity> M = f.view();
  std::vector<FittedRun> fitted;
  for (size_t i = 0; i < judged.series.size(); ++i) {
    const Series& s = judged.series[i];
    const Dataset d = build_dataset(s, M.nd, M.dd);
    FittedRun r;
    r.name = s.name;
    r.section = fit_section(s.name + " (" + std::to_string(d.rows()) + " rows), model " + a.model + " of rig " +
                                target.name,
                            f, baseline, d, d.pieces, target, judged.horizons[i]);
    if (drawn) {
      r.time = label_times(s, M.nd, M.dd, target.rate_hz > 0 ? 1.0 / target.rate_hz : 0.0);
      r.y = measured(d, d.pieces);
      r.net = simulate_network(f, d, d.pieces).free_run;
      if (baseline) r.arx = simulate_arx(*baseline, d, d.pieces).free_run;
    }
    fitted.push_back(std::move(r));
  }
  return fitted;
}

// The tables, or one JSON object; nothing when the image goes to stdout.
void print_fit(const FitArgs& a, const std::string& image, const Model<HostCapacity>& M, const PlantTarget& target,
               const std::vector<FittedRun>& fitted, bool has_baseline, const std::string& arx_from) {
  if (image == "-") return;
  if (!a.json) {
    std::printf("model %s (hash 0x%08x), rig %s; ARX baseline on the same lags (nd = %d, dd = %d): %s\n",
                a.model.c_str(), M.hash, target.name.c_str(), M.nd, M.dd,
                has_baseline ? arx_from.c_str() : "none kept with this model (--train-run ID fits one from a recorded run)");
    for (const FittedRun& r : fitted) std::printf("%s", section_table(r.section, target.y_unit).c_str());
    return;
  }
  nlohmann::json j;
  j["model"] = a.model;
  j["hash"] = M.hash;
  j["rig"] = target.name;
  j["unit"] = target.y_unit;
  j["arx"] = arx_from;
  j["runs"] = nlohmann::json::array();
  for (const FittedRun& r : fitted) {
    nlohmann::json s = nlohmann::json::parse(section_to_json(r.section, target.y_unit));
    s["data"] = r.name;
    j["runs"].push_back(s);
  }
  std::printf("%s\n", j.dump(2).c_str());
}

void run_fit(const FitArgs& a, const TargetResolver& resolve, const PlatformNamer& name_platform,
             const RunLoader& load_run, const ScriptPlotter& plot) {
  if (a.model.empty()) throw PipelineError("MODEL is required (see --help)");
  if (a.runs.empty() && a.data.empty())
    throw PipelineError("give the data to judge the model on: --run ID (a recorded run) or --data FILE.csv");
  if (!a.svg.empty() && !a.png.empty()) throw PipelineError("give --svg FILE or --png FILE, not both");
  const std::string image = a.svg.empty() ? a.png : a.svg;
  if (!image.empty()) {
    if (!plot) throw PipelineError("--svg/--png need gnuplot through the console, which this build lacks");
    check_image_path(image);
  }
  const ModelFile f = load_model_file(a.model);
  const Model<HostCapacity> M = f.view();
  const bool has_fit = !f.fit.empty();
  const ModelFit stored = has_fit ? fit_from_json(f.fit, a.model) : ModelFit{};
  const PlantTarget target = fit_target(a, f, stored, has_fit, resolve, name_platform);
  // Every input read, and refused, before anything is printed or drawn.
  const Judged judged = judged_data(a, target, load_run);
  std::string arx_from;
  const ArxModel arx = baseline_arx(a, target, M, stored, load_run, arx_from);
  const ArxModel* baseline = arx.theta.size() > 0 ? &arx : nullptr;
  const std::vector<FittedRun> fitted = fit_runs(a, f, target, judged, baseline, !image.empty());
  std::string drawn;
  if (!image.empty()) drawn = plot(fit_plot_script(fitted, a.model, target.y_unit, a.svg.empty() ? FitImage::Png : FitImage::Svg));
  print_fit(a, image, M, target, fitted, baseline != nullptr, arx_from);
  if (!image.empty()) {
    OutputFile out(image);
    if (std::fwrite(drawn.data(), 1, drawn.size(), out.get()) != drawn.size())
      throw PipelineError("cannot write " + image);
    out.commit();
    if (image != "-") std::fprintf(stderr, "model fit drawn to %s\n", image.c_str());
  }
}

}  // namespace

void add_model_fit_command(CLI::App& model_command, TargetResolver resolve, PlatformNamer name_platform, RunLoader load_run,
                           ScriptPlotter plot) {
  auto args = std::make_shared<FitArgs>();
  CLI::App* fit = model_command.add_subcommand(
      "fit",
      "Judge a model on recorded runs or files as system identification does: per run, a free-run\n"
      "simulation (the y history fed the model's own predictions, driven by the run's recorded u and\n"
      "sensors l), one-step prediction and, for a recorded run, prediction as far ahead as its\n"
      "controller's horizon N looked (the figure that says whether the model is still right where\n"
      "the controller works); per output RMSE (its unit), nRMSE (of its span) and\n"
      "fit % = 100 (1 - |y - yhat| / |y - mean(y)|), as MATLAB's compare. Beside it, the linear ARX\n"
      "baseline on the same lags that train kept with the model (or refitted from --train-run).\n"
      "Example: nlsoft-console model fit arm.nlsm --run 4 --svg fit.svg\n"
      "         nlsoft-console model fit arm.nlsm --rig lab/arm.toml --data arm-test.csv --json");
  fit->add_option("model", args->model, "model file (required)")->type_name("MODEL");
  fit->add_option("--run", args->runs, "a recorded run to judge it on (runs list); repeat for several")
      ->type_name("ID");
  fit->add_option("--data", args->data, "a dataset CSV or a run export (as train --data); repeat for several")
      ->type_name("FILE");
  fit->add_option("--db", args->db, "the runs' database (default: the console's, as `runs list`)")->type_name("FILE");
  add_rig_option(fit, args->rig, "the rig (default: the one the model was trained for)");
  fit->add_option("--train-run", args->train_runs, "refit the ARX baseline on this run; repeat for several")
      ->type_name("ID");
  fit->add_option("--svg", args->svg, "draw measured against simulated outputs to an SVG ('-': standard output)")
      ->type_name("FILE");
  fit->add_option("--png", args->png, "the same as a PNG")->type_name("FILE");
  fit->add_flag("--json", args->json, "print the figures as JSON");
  fit->add_option("--horizon", args->horizon,
                  "also score predictions K steps ahead (default: a run's controller horizon N as it started; "
                  "0: not)")
      ->type_name("K")
      ->check(CLI::Range(0, 1000));
  fit->callback([args, resolve, name_platform, load_run, plot] { run_fit(*args, resolve, name_platform, load_run, plot); });
}

}  // namespace nlsoft::console
