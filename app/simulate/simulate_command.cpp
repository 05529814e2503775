#include "app/simulate/simulate_command.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "host/files/cli_error.hpp"
#include "app/simulate/closed_loop.hpp"
#include "app/metrics/tracking_metrics.hpp"
#include "host/files/output_file.hpp"
#include "app/simulate/model_loader.hpp"
#include "app/simulate/param_args.hpp"
#include "app/simulate/rig_loop.hpp"
#include "app/progress_bar.hpp"
#include "host/paths/install_paths.hpp"
#include "app/reference_names.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_params.hpp"
#include "host/rig/rig_plant.hpp"
#include "host/rig/rig_option.hpp"

namespace nlsoft::console {

using host::CliError;
using host::CliExit;
using host::Lookup;
using host::OutputFile;
using host::Rig;
using host::RigInput;
using host::RigOutput;
using host::add_rig_option;
using host::find_model_file;
using host::load_rig_arg;
using host::rig_arg_help;
using host::rig_arg_validator;
using host::rig_params;

namespace {

// The nRMSE the README holds the simulated rigs to.
constexpr double kTrackingTarget = 0.05;
// An input this long within 1 % of its range of a limit is said to ride it.
constexpr double kRidingLimit = 0.5;

std::string input_name(const Rig& rig, int i) {
  return size_t(i) < rig.inputs.size() && !rig.inputs[size_t(i)].name.empty() ? rig.inputs[size_t(i)].name
                                                                                : fmt::format("u{}", i);
}

struct SimulateOptions {
  std::string rig = "hasel";
  std::string reference;
  std::string controller = "mpc";
  std::string mode = "exact";
  long steps = 0;
  std::vector<std::string> sets;
  std::string model;
  std::string csv, svg, png;
  uint32_t seed = 1;
  bool json = false;
};

void write_trace_csv(const std::string& path, const Trace& t) {
  OutputFile out(path);
  std::FILE* f = out.get();
  fmt::print(f, "step,time_s");
  for (const char* col : {"y_ref", "y_hat", "y_true"})
    for (int i = 0; i < t.n; ++i) fmt::print(f, ",{}{}", col, i);
  for (int i = 0; i < t.m; ++i) fmt::print(f, ",u{}", i);
  fmt::print(f, ",cost,iterations,flags\n");
  for (long k = 0; k < t.rows(); ++k) {
    fmt::print(f, "{},{:.9g}", k, double(k + 1) * double(t.dt));
    for (const auto* v : {&t.y_ref, &t.y_hat, &t.y_true})
      for (int i = 0; i < t.n; ++i) fmt::print(f, ",{:.9g}", (*v)[size_t(k * t.n + i)]);
    for (int i = 0; i < t.m; ++i) fmt::print(f, ",{:.9g}", t.u[size_t(k * t.m + i)]);
    fmt::print(f, ",{:.9g},{},{}\n", t.cost[size_t(k)], int(t.iterations[size_t(k)]), int(t.flags[size_t(k)]));
  }
  out.commit();
}

// The controller the options and the rig's file set: its kind, the rig's
// parameters with --set's writes, the derivative mode.
void configure_controller(const SimulateOptions& o, const Rig& rig, LoopSetup& setup) {
  if (o.controller == "pid")
    use_rig_pid(rig, setup);
  else if (o.controller != "mpc")
    throw CliError(fmt::format("unknown controller '{}'; use mpc or pid", o.controller));
  if (rig_params(rig, setup.params) != Status::Ok)
    throw CliError(fmt::format("rig '{}' ({}): m = {}, n = {}, N = {}, Nc = {} exceed the console's controller "
                               "(m <= {}, n <= {}, N <= {}, Nc <= {})",
                               rig.name, rig.file, rig.m(), rig.n(), rig.controller.N, rig.controller.Nc,
                               HostCapacity::m, HostCapacity::n, HostCapacity::N, HostCapacity::Nc));
  if (o.mode == "fd")
    setup.params.mode = DerivMode::Fd;
  else if (o.mode != "exact")
    throw CliError(fmt::format("unknown derivative mode '{}'; use exact or fd", o.mode));
  std::vector<ParamWrite> writes;
  for (const std::string& s : o.sets) writes.push_back(parse_param_write(s, rig.m(), rig.n()));
  apply_param_writes(setup.params, writes, rig.m(), rig.n());
}

// The model file MPC runs: --model, else the rig's [model] file where the
// models are looked for.
std::string model_path(const SimulateOptions& o, const Rig& rig) {
  if (!o.model.empty()) return o.model;
  if (rig.model.file.empty())
    throw CliError(fmt::format("rig '{}' ({}) names no [model] file; pass --model FILE (a model file from "
                               "`nlsoft-console train`)",
                               rig.name, rig.file));
  const Lookup found = find_model_file(rig.model.file);
  if (found.found.empty())
    throw CliError(fmt::format("no model for '{}'; looked in:{}\npass --model FILE (a model file from "
                               "`nlsoft-console train`) or set NLSOFT_MODELS",
                               o.rig, found.tried_lines()));
  return found.found;
}

// What a simulated run is judged by: tracking of the true and the predicted
// outputs, step responses, and how the inputs worked.
struct Figures {
  TrackingMetrics tm, pm;
  std::vector<StepResponse> steps;
  InputMetrics im;
};

Figures figures(const LoopSetup& setup, const Trace& t) {
  Figures f;
  const float* weight = setup.controller == ControllerKind::Mpc ? setup.params.Q : nullptr;
  f.tm = tracking_metrics(t.y_ref, t.y_true, t.n, weight);
  f.pm = tracking_metrics(t.y_ref, t.y_hat, t.n, weight);
  double iters = 0;
  for (uint8_t i : t.iterations) iters += i;
  f.tm.mean_iterations = t.rows() ? iters / double(t.rows()) : 0;
  f.tm.solve_p50_us = percentile(t.solve_us, 0.5);
  f.tm.solve_p99_us = percentile(t.solve_us, 0.99);
  f.steps = step_responses(setup.reference, t.y_true, t.n, 0, t.dt);
  // How hard the inputs worked and how long each rode a limit: the same
  // figures (and names) as a recorded run's (app/record/run_metrics.hpp).
  f.im = input_metrics(t.u, t.m, std::vector<float>(setup.params.u_min, setup.params.u_min + t.m),
                       std::vector<float>(setup.params.u_max, setup.params.u_max + t.m));
  return f;
}

void draw(const std::string& image, const SimulateOptions& o, const Rig& rig, const std::string& ref_name,
          const Trace& t, const Figures& f, const SimulationPlotter& plot) {
  SimulationPicture pic{&t, rig.name, ref_name, f.tm, f.pm, !o.svg.empty(), {}, {}};
  for (const RigOutput& y : rig.outputs) pic.output_labels.push_back(y.unit.empty() ? y.name : y.name + " (" + y.unit + ")");
  for (const RigInput& u : rig.inputs) pic.input_labels.push_back(u.unit.empty() ? u.name : u.name + " (" + u.unit + ")");
  const std::string bytes = plot(pic);
  OutputFile out(image);
  if (std::fwrite(bytes.data(), 1, bytes.size(), out.get()) != bytes.size())
    throw CliError(fmt::format("cannot write {}", image));
  out.commit();
  if (image != "-") fmt::print(stderr, "simulation drawn to {}\n", image);
}

void print_json(const SimulateOptions& o, const std::string& ref_name, const Trace& t, const std::string& model,
                const Figures& f) {
  const TrackingMetrics& tm = f.tm;
  nlohmann::json j;
  j["platform"] = o.rig;
  j["reference"] = ref_name;
  j["controller"] = o.controller;
  j["mode"] = o.mode;
  j["samples"] = t.rows();
  j["duration_s"] = double(t.rows()) * double(t.dt);
  j["model"] = model;
  j["rmse"] = tm.rmse;
  j["nrmse"] = tm.nrmse;
  j["nrmse_all_axes"] = tm.nrmse_all;
  j["tracked_axes"] = tm.tracked;
  j["tracking_signal"] = "y_true";
  j["max_error"] = tm.max_error;
  j["nrmse_hat"] = f.pm.nrmse;
  j["iterations"] = tm.mean_iterations;
  j["compute_p50_us"] = tm.solve_p50_us;
  j["compute_p99_us"] = tm.solve_p99_us;
  j["u_effort"] = f.im.u_effort;
  j["u_saturated"] = f.im.u_saturated;
  j["u_saturated_per_input"] = f.im.saturated_per_input;
  if (!f.steps.empty()) {
    j["step_response"] = nlohmann::json::array();
    for (const auto& s : f.steps)
      j["step_response"].push_back({{"from", s.from}, {"to", s.to}, {"rise_s", s.rise_s},
                                    {"overshoot_pct", s.overshoot_pct}, {"steady_error", s.steady_error}});
  }
  fmt::print("{}\n", j.dump());
}

void print_text(const SimulateOptions& o, const Rig& rig, const std::string& ref_name, const LoopSetup& setup,
                const Trace& t, const std::string& model, const Figures& f) {
  const TrackingMetrics& tm = f.tm;
  const InputMetrics& im = f.im;
  fmt::print("{} on {}, {} steps ({:.1f} s), controller {}{}\n", ref_name, o.rig, t.rows(),
             double(t.rows()) * double(t.dt), o.controller, setup.controller == ControllerKind::Mpc ? ", mode " + o.mode : "");
  if (setup.model) fmt::print("model       {}\n", model);
  std::string rm;
  for (double r : tm.rmse) rm += fmt::format("{:.4g} ", r);
  fmt::print("RMSE        {}(true output vs reference, per axis)\n", rm);
  std::string axes;
  for (int i : tm.tracked) axes += fmt::format("y{} ", i);
  auto pct = [](double v) { return std::isnan(v) ? std::string("n/a (flat reference)") : fmt::format("{:.2f} %", 100 * v); };
  fmt::print("nRMSE       {} over the tracked axes {}(predicted path: {})\n", pct(tm.nrmse), axes, pct(f.pm.nrmse));
  if (tm.nrmse > kTrackingTarget)
    fmt::print("            above the {:g} % target (README, \"Tracking on the simulated rigs\"): a model trained on "
               "more data, or Q and Lambda tuned, may close the gap\n",
               100 * kTrackingTarget);
  if (int(tm.tracked.size()) < t.n)
    fmt::print("            {} over every axis (an axis with Q < 1e-3 max Q is not tracked)\n", pct(tm.nrmse_all));
  fmt::print("max error   {:.4g}\n", tm.max_error);
  if (setup.controller == ControllerKind::Mpc)
    fmt::print("NR          {:.2f} iterations per step on average\n", tm.mean_iterations);
  std::string per;
  for (size_t i = 0; i < im.saturated_per_input.size(); ++i)
    per += fmt::format("{}{} {:.0f} %", i ? ", " : "", input_name(rig, int(i)), 100 * im.saturated_per_input[i]);
  fmt::print("inputs      effort {:.4g} (RMS step change over the range); at a limit: {}\n", im.u_effort, per);
  for (size_t i = 0; i < im.saturated_per_input.size(); ++i)
    if (im.saturated_per_input[i] > kRidingLimit)
      fmt::print("            {} rides its limit {:.0f} % of the steps: the controller is clipped there, not "
                 "tracking (a wider u range, a larger Lambda or a reachable reference)\n",
                 input_name(rig, int(i)), 100 * im.saturated_per_input[i]);
  fmt::print("solve time  p50 {:.1f} us, p99 {:.1f} us (this host)\n", tm.solve_p50_us, tm.solve_p99_us);
  for (const auto& s : f.steps)
    fmt::print("step {:g} -> {:g}: rise 0-90 % {}, overshoot {:.2f} %, steady error {:.2f} mm\n", s.from, s.to,
               s.rise_s < 0 ? std::string("not reached") : fmt::format("{:.3f} s", s.rise_s), s.overshoot_pct,
               1000 * s.steady_error);
}

int run_simulate(const SimulateOptions& o, const SimulationPlotter& plot) {
  if (!o.svg.empty() && !o.png.empty()) throw CliError("simulate: give --svg FILE or --png FILE, not both");
  const std::string image = o.svg.empty() ? o.png : o.svg;
  if (!image.empty() && !plot) throw CliError("simulate --svg/--png: this build has no plotting (runs plot)");
  // The rig by name or file: its plant, controller defaults, references,
  // model and rate.
  const Rig rig = load_rig_arg(o.rig);
  const std::string ref_name = o.reference.empty() ? default_reference(rig) : o.reference;

  LoopSetup setup;
  GenericPlantSpec generic{};
  use_rig_plant(rig, "simulate", generic, setup);
  setup.reference = reference_by_name(rig, ref_name);
  setup.seed = o.seed;
  configure_controller(o, rig, setup);
  auto model = std::make_unique<LoadedModel>();
  if (setup.controller == ControllerKind::Mpc) {
    load_model(model_path(o, rig), *model);
    setup.model = &model->model;
  }
  const float rate_hz = float(rig.rate_hz);
  const uint32_t len = reference_length(setup.reference);
  setup.steps = o.steps > 0 ? o.steps : (len > 0 ? long(len) : long(20.0f * rate_hz));
  setup.settle_steps = long(2.0f * rate_hz);

  Trace t;
  {
    ProgressBar bar(fmt::format("simulate {} {}", o.rig, ref_name));
    t = run_closed_loop(setup, [&](long d, long n) { bar.update(d, n); });
  }
  if (!o.csv.empty()) write_trace_csv(o.csv, t);
  const Figures f = figures(setup, t);
  if (!image.empty()) draw(image, o, rig, ref_name, t, f, plot);
  const std::string model_file = setup.model ? model->path : "";
  if (o.json)
    print_json(o, ref_name, t, model_file, f);
  else
    print_text(o, rig, ref_name, setup, t, model_file, f);
  return 0;
}

}  // namespace

void add_simulate_command(CLI::App& app, SimulationPlotter plot) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand(
      "simulate",
      "Run plant + controller offline on this machine and print tracking metrics.\n"
      "The plant is a simulated rig; the controller only sees the learned model.\n"
      "Examples:\n"
      "  nlsoft-console simulate --rig hasel                 (Swirl, default model)\n"
      "  nlsoft-console simulate --rig msd --controller pid  (the paper's baseline)\n"
      "  nlsoft-console simulate --rig tendon --set Q=0,5e3,2e3 --mode fd --json\n"
      "  nlsoft-console simulate --rig my-hasel.toml         (a rig file: docs/rig-file.md)");
  add_rig_option(sub, o->rig, "the rig: " + rig_arg_help() + "; it needs a [plant]")
      ->check(rig_arg_validator())
      ->capture_default_str();
  sub->add_option("--reference", o->reference,
                  "infinity, pringle, diagonal, swirl, steps or hold (default: the rig's [reference] kind)");
  sub->add_option("--controller", o->controller, "mpc or pid (pid: the rig file's [pid] gains)")->capture_default_str();
  sub->add_option("--mode", o->mode, "derivatives: exact (chain rule) or fd (central differences)")
      ->capture_default_str();
  sub->add_option("--steps", o->steps, "control steps to run (default: the whole reference, or 20 s)")
      ->check(CLI::Range(1L, 100000000L));
  sub->add_option("--set", o->sets, "override a parameter, NAME=V[,V...], e.g. --set Q=1e6,2e6,1e6; one value sets every element (--set Lambda=1e8) (repeatable)");
  sub->add_option("--model", o->model, "model file (default: the rig's [model] file, among the shipped models)");
  sub->add_option("--csv", o->csv, "also write the whole trace to this CSV file");
  sub->add_option("--svg", o->svg, "also draw it to this SVG file (as runs plot draws a recorded run; gnuplot)");
  sub->add_option("--png", o->png, "also draw it to this PNG file");
  sub->add_option("--seed", o->seed, "plant noise seed")->capture_default_str();
  sub->add_flag("--json", o->json, "print one JSON object instead of the table");
  sub->callback([o, plot]() { throw CliExit{run_simulate(*o, plot)}; });
}

}  // namespace nlsoft::console
