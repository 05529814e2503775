// The offline closed loop with the shipped models: the product's tracking
// claims, asserted on the true plant output.
#include <gtest/gtest.h>

#include "app/cli_error.hpp"
#include "app/simulate/closed_loop.hpp"
#include "app/metrics/tracking_metrics.hpp"
#include "app/simulate/model_loader.hpp"
#include "app/reference_names.hpp"
#include "shared/platform.hpp"
#include "shared/sim_plant.hpp"

using namespace nlsoft;
using namespace nlsoft::console;

namespace {

struct Run {
  LoopSetup setup;
  Trace trace;
  TrackingMetrics metrics;
};

std::unique_ptr<Run> run(PlatformId platform, const std::string& ref, ControllerKind kind = ControllerKind::Mpc,
                         DerivMode mode = DerivMode::Exact) {
  static LoadedModel models[3];
  auto r = std::make_unique<Run>();
  LoopSetup& s = r->setup;
  s.platform = platform;
  s.controller = kind;
  s.reference = reference_preset(platform, ref);
  EXPECT_EQ(preset_params(preset(platform), s.params), Status::Ok);
  SimPlant plant;
  plant.select(platform);
  plant.input_limits(s.params.u_min, s.params.u_max);
  s.params.mode = mode;
  LoadedModel& lm = models[int(platform)];
  if (lm.path.empty()) load_model(default_model_path(platform), lm);
  s.model = &lm.model;
  s.steps = long(reference_length(s.reference));
  if (s.steps == 0) s.steps = long(20 * preset(platform).rate_hz);
  s.settle_steps = long(2 * preset(platform).rate_hz);
  r->trace = run_closed_loop(s);
  r->metrics = tracking_metrics(r->trace.y_ref, r->trace.y_true, r->trace.n, s.params.Q);
  return r;
}

}  // namespace

TEST(ClosedLoop, ShippedModelsExist) {
  for (PlatformId p : {PlatformId::Msd, PlatformId::Hasel, PlatformId::Tendon})
    EXPECT_FALSE(default_model_path(p).empty()) << platform_name(p);
}

TEST(ClosedLoop, HaselSwirlTracksWithinFivePercent) {
  const auto r = run(PlatformId::Hasel, "swirl");
  EXPECT_LE(r->metrics.nrmse, 0.05);
  EXPECT_EQ(r->metrics.tracked.size(), 3u);
  for (float u : r->trace.u) {
    ASSERT_GE(u, 0.0f);
    ASSERT_LE(u, 1.0f);
  }
}

TEST(ClosedLoop, HaselSwirlInFdModeTracksToo) {
  const auto r = run(PlatformId::Hasel, "swirl", ControllerKind::Mpc, DerivMode::Fd);
  EXPECT_LE(r->metrics.nrmse, 0.05);
}

TEST(ClosedLoop, TendonInfinityTracksTheWeightedAxes) {
  const auto r = run(PlatformId::Tendon, "infinity");
  EXPECT_LE(r->metrics.nrmse, 0.05);
  ASSERT_EQ(r->metrics.tracked.size(), 2u);  // y0 has Q = 1e-3: the bowl's depth
  EXPECT_EQ(r->metrics.tracked[0], 1);
}

TEST(ClosedLoop, MsdStepsMatchThePapersShape) {
  const auto r = run(PlatformId::Msd, "steps");
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
  const auto r = run(PlatformId::Msd, "steps", ControllerKind::Pid);
  const auto steps = step_responses(r->setup.reference, r->trace.y_true, 1, 0, r->trace.dt);
  ASSERT_EQ(steps.size(), 3u);
  for (const auto& s : steps) EXPECT_GT(s.rise_s, 0.0);
}

TEST(ClosedLoop, RefusesWhatCannotRun) {
  LoopSetup s;
  s.platform = PlatformId::Hasel;
  s.steps = 10;
  s.reference = reference_preset(PlatformId::Hasel, "hold");
  EXPECT_THROW(run_closed_loop(s), CliError);  // MPC without a model
  s.controller = ControllerKind::Pid;
  EXPECT_THROW(run_closed_loop(s), CliError);  // PID on a 6-input rig
  LoadedModel msd;
  load_model(default_model_path(PlatformId::Msd), msd);
  s.controller = ControllerKind::Mpc;
  s.model = &msd.model;
  EXPECT_THROW(run_closed_loop(s), CliError);  // msd model on the hasel rig
}
