// A closed-loop TELEMETRY is one instant (PROTOCOL.md 9.6, protocol 1.8):
// the output measured at step k beside the reference r(k) and prediction
// y_hat(k) that step k - 1 made for it. Checked on the simulator's own
// firmware in this process (app/replay/simulator_in_process.hpp), which is
// deterministic: no pty, no clock.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "app/link/device.hpp"
#include "app/replay/simulator_in_process.hpp"
#include "app/simulate/model_loader.hpp"
#include "host/paths/install_paths.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_reference.hpp"
#include "protocol/messages.hpp"
#include "shared/reference.hpp"

namespace {

namespace p = nlsoft::protocol;
using namespace nlsoft;
using namespace nlsoft::console;
using nlsoft::host::Rig;
using nlsoft::host::find_model_file;
using nlsoft::host::load_rig_arg;
using nlsoft::host::rig_reference;

struct Recorded {
  RefParams ref{};
  std::vector<p::Telemetry> t;
  int n = 0;
};

// `steps` closed-loop steps of `rig` tracking its default task's Infinity,
// every step's TELEMETRY.
Recorded run_infinity(const std::string& rig_name, uint32_t steps) {
  const Rig rig = load_rig_arg(rig_name);
  LoadedModel model;
  load_model(find_model_file(rig.model.file).found, model);
  SimulatorInProcess sim(rig, model.file, 1);
  Recorded r;
  r.n = rig.n();
  r.ref = rig_reference(rig, rig_name == "msd" ? RefKind::Step : RefKind::Infinity);
  p::Ack ack;
  EXPECT_TRUE(sim.request(ref_select_of(r.ref)).as(ack));
  p::TelemetryConfig tc;
  tc.mask = p::telemetry_field::kAll;
  tc.decimation = 1;
  EXPECT_TRUE(sim.request(tc).as(ack));
  p::RunStart rs;
  rs.run_id = 1;
  EXPECT_TRUE(sim.request(rs).as(ack));
  for (uint32_t k = 0; k < steps; ++k) {
    sim.step();
    if (k % 10 == 0) sim.request(p::Ping{});  // the link watchdog stays fed
    for (const SimFrame& f : sim.take_frames()) {
      p::Telemetry t;
      if (f.as(t)) r.t.push_back(t);
    }
  }
  return r;
}

double mean_abs(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += std::fabs(x);
  return v.empty() ? 0.0 : s / double(v.size());
}

class SampleInstant : public ::testing::TestWithParam<const char*> {};

TEST_P(SampleInstant, TheReferenceAndPredictionAreThoseOfTheMeasuredOutputsStep) {
  const Recorded r = run_infinity(GetParam(), 2000);
  ASSERT_EQ(r.t.size(), 2000u);
  const int n = r.n;
  // The controller at step k aims at r(k+1) .. (the rows closed_loop.cpp
  // and the firmware's reference slot both take from reference_at(k + 1));
  // the sample of step k carries r(k), the first one its own r(1).
  for (size_t i = 0; i < r.t.size(); ++i) {
    const uint32_t k = r.t[i].step;
    ASSERT_EQ(k, uint32_t(i));
    float want[kRefMaxDim] = {};
    reference_at(r.ref, nullptr, k == 0 ? 1u : k, want, n);
    for (int j = 0; j < std::min(n, kRefMaxDim); ++j)
      ASSERT_FLOAT_EQ(r.t[i].y_ref[j], want[j]) << "step " << k << " output " << j;
  }
  // The first step had no step before it: it sends its own aim and
  // prediction, which the second step then sends as the aim and
  // prediction made for it.
  for (int j = 0; j < n; ++j) {
    EXPECT_EQ(r.t[0].y_ref[j], r.t[1].y_ref[j]);
    EXPECT_EQ(r.t[0].y_hat[j], r.t[1].y_hat[j]);
  }
  // y_hat(k) is the prediction of y(k). Where the controller feeds back
  // the measured output (msd), it is a one-step prediction: where the
  // output moves, nearer y(k) than the output measured a step earlier
  // (the 1.7 pairing). hasel's and tendon's controllers run the model on
  // its own predictions, whose error is an offset larger than a step's
  // motion, so that comparison says nothing there.
  if (std::string(GetParam()) != "msd") return;
  std::vector<double> now, lagged, moved;
  for (size_t i = 2; i < r.t.size(); ++i)
    for (int j = 0; j < n; ++j) moved.push_back(std::fabs(double(r.t[i].y_true[j]) - double(r.t[i - 1].y_true[j])));
  std::vector<double> sorted = moved;
  std::sort(sorted.begin(), sorted.end());
  const double fast = sorted[sorted.size() * 3 / 4];
  for (size_t i = 2, at = 0; i < r.t.size(); ++i)
    for (int j = 0; j < n; ++j, ++at) {
      if (moved[at] < fast) continue;
      now.push_back(double(r.t[i].y_hat[j]) - double(r.t[i].y_true[j]));
      lagged.push_back(double(r.t[i].y_hat[j]) - double(r.t[i - 1].y_true[j]));
    }
  std::printf("msd, where the output moved most: prediction error %.4g at one instant, %.4g paired as in 1.7\n",
              mean_abs(now), mean_abs(lagged));
  EXPECT_LT(mean_abs(now), 0.5 * mean_abs(lagged)) << "one-step prediction error " << mean_abs(now)
                                                    << " against the 1.7 pairing's " << mean_abs(lagged)
                                                    << " where the output moved most (over " << fast << " a step)";
}

INSTANTIATE_TEST_SUITE_P(ShippedRigs, SampleInstant, ::testing::Values("hasel", "tendon", "msd"));

}  // namespace
