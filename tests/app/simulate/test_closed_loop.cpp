// The offline closed loop with the shipped models: the product's tracking
// claims, asserted on the true plant output.
#include <gtest/gtest.h>

#include <map>

#include "host/files/cli_error.hpp"
#include "app/simulate/closed_loop.hpp"
#include "app/metrics/tracking_metrics.hpp"
#include "app/simulate/model_loader.hpp"
#include "app/simulate/rig_loop.hpp"
#include "app/reference_names.hpp"
#include "host/rig/rig.hpp"
#include "host/rig/rig_params.hpp"
#include "host/paths/install_paths.hpp"
#include "shared/sim_plant.hpp"

using namespace nlsoft;
using namespace nlsoft::console;
using nlsoft::host::CliError;
using nlsoft::host::Rig;
using nlsoft::host::find_model_file;
using nlsoft::host::load_rig;
using nlsoft::host::rig_params;

namespace {

struct Run {
  LoopSetup setup;
  Trace trace;
  TrackingMetrics metrics;
};

// A shipped rig as its file describes it.
Rig shipped(const std::string& name) { return load_rig(std::string(NLSOFT_RIGS_DIR) + "/" + name + ".toml"); }

// The shipped model a rig file names.
std::string model_path(const Rig& rig) { return find_model_file(rig.model.file).found; }

std::unique_ptr<Run> run(const std::string& name, const std::string& ref, ControllerKind kind = ControllerKind::Mpc,
                         DerivMode mode = DerivMode::Exact) {
  static std::map<std::string, LoadedModel> models;
  const Rig rig = shipped(name);
  auto r = std::make_unique<Run>();
  LoopSetup& s = r->setup;
  s.plant = rig.plant.kind->kind;
  s.controller = kind;
  if (kind == ControllerKind::Pid) use_rig_pid(rig, s);  // its file's [pid]
  s.reference = reference_by_name(rig, ref);
  EXPECT_EQ(rig_params(rig, s.params), Status::Ok);
  s.params.mode = mode;
  LoadedModel& lm = models[name];
  if (lm.path.empty()) load_model(model_path(rig), lm);
  s.model = &lm.model;
  s.steps = long(reference_length(s.reference));
  if (s.steps == 0) s.steps = long(20 * rig.rate_hz);
  s.settle_steps = long(2 * rig.rate_hz);
  r->trace = run_closed_loop(s);
  r->metrics = tracking_metrics(r->trace.y_ref, r->trace.y_true, r->trace.n, s.params.Q);
  return r;
}

}  // namespace

TEST(ClosedLoop, ShippedModelsExist) {
  for (const char* name : {"msd", "hasel", "tendon"}) EXPECT_FALSE(model_path(shipped(name)).empty()) << name;
}

TEST(ClosedLoop, HaselSwirlTracksWithinFivePercent) {
  const auto r = run("hasel", "swirl");
  EXPECT_LE(r->metrics.nrmse, 0.05);
  EXPECT_EQ(r->metrics.tracked.size(), 3u);
  for (float u : r->trace.u) {
    ASSERT_GE(u, 0.0f);
    ASSERT_LE(u, 1.0f);
  }
}

TEST(ClosedLoop, HaselSwirlInFdModeTracksToo) {
  const auto r = run("hasel", "swirl", ControllerKind::Mpc, DerivMode::Fd);
  EXPECT_LE(r->metrics.nrmse, 0.05);
}

TEST(ClosedLoop, TendonInfinityTracksTheWeightedAxes) {
  const auto r = run("tendon", "infinity");
  EXPECT_LE(r->metrics.nrmse, 0.05);
  ASSERT_EQ(r->metrics.tracked.size(), 2u);  // y0 has Q = 1e-3: the bowl's depth
  EXPECT_EQ(r->metrics.tracked[0], 1);
}

TEST(ClosedLoop, MsdStepsMatchThePapersShape) {
  const auto r = run("msd", "steps");
  const auto steps = step_responses(r->setup.reference, r->trace.y_true, 1, 0, r->trace.dt);
  ASSERT_EQ(steps.size(), 3u);
  for (const auto& s : steps) {
    EXPECT_GT(s.rise_s, 0.0) << "step to " << s.to << " never reached 90 %";
    EXPECT_LT(s.rise_s, 1.0);
    EXPECT_LT(s.overshoot_pct, 5.0);
    EXPECT_LT(s.steady_error, 5e-3);  // m
  }
}

TEST(ClosedLoop, PidBaselineSettlesOnMsd) {
  const auto r = run("msd", "steps", ControllerKind::Pid);
  const auto steps = step_responses(r->setup.reference, r->trace.y_true, 1, 0, r->trace.dt);
  ASSERT_EQ(steps.size(), 3u);
  for (const auto& s : steps) EXPECT_GT(s.rise_s, 0.0);
}

TEST(ClosedLoop, RefusesWhatCannotRun) {
  LoopSetup s;
  s.plant = PlantKind::Hasel;
  s.steps = 10;
  s.reference = reference_by_name(shipped("hasel"), "hold");
  EXPECT_THROW(run_closed_loop(s), CliError);  // MPC without a model
  s.controller = ControllerKind::Pid;
  EXPECT_THROW(run_closed_loop(s), CliError);  // PID on a 6-input rig
  LoadedModel msd;
  load_model(model_path(shipped("msd")), msd);
  s.controller = ControllerKind::Mpc;
  s.model = &msd.model;
  EXPECT_THROW(run_closed_loop(s), CliError);  // msd model on the hasel rig
  // A kind no registry row carries, or the generic plant without its spec:
  // refused by name, never another plant in its place.
  s.controller = ControllerKind::Pid;
  for (PlantKind k : {static_cast<PlantKind>(9), PlantKind::Generic}) {
    s.plant = k;
    try {
      run_closed_loop(s);
      ADD_FAILURE() << "ran plant kind " << int(k);
    } catch (const CliError& e) {
      EXPECT_NE(std::string(e.what()).find("is no hand-written plant"), std::string::npos) << e.what();
    }
  }
}
