// Whole control steps: the output is finite and inside its limits whatever
// the parameters and inputs, and the loop tracks when the model is the plant.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "shared/controller.hpp"
#include "support/random_model.hpp"
#include "support/rig_capacities.hpp"
#include "support/shipped_rigs.hpp"

using namespace nlsoft;
using Cap = HostCapacity;

namespace {

test::OwnedModel<Cap> tendon_like(unsigned seed) {
  return test::random_model<Cap>(2, 3, 11, 2,
                                 {{LayerKind::Gru, 5, Activation::Tanh, Activation::HardSigmoid, true},
                                  {LayerKind::Dense, 5, Activation::Relu},
                                  {LayerKind::Dense, 3, Activation::Tanh}},
                                 seed, 0.8f);
}

}  // namespace

struct Hostile {
  const char* what;
  void (*apply)(Params<Cap>&);
};

class HostileParams : public ::testing::TestWithParam<Hostile> {};

TEST_P(HostileParams, OutputStaysFiniteAndClamped) {
  auto o = tendon_like(3);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  Params<Cap> P;
  P = test::shipped_params<Cap>("tendon");
  GetParam().apply(P);
  static Controller<Cap> ctl;
  ASSERT_EQ(ctl.configure(&o.model, P), Status::Ok);
  const float u0[2] = {0, 0}, y0[3] = {0, 0, 0};
  float l[11] = {};
  ctl.reset(u0, y0, l);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> d(-3.0f, 3.0f);
  for (int k = 0; k < 200; ++k) {
    float ref[Cap::N * 3];
    for (float& v : ref) v = d(rng) * 100.0f;
    for (float& v : l) v = d(rng);
    if (k % 7 == 0) l[k % 11] = std::nanf("");
    if (k % 11 == 0) ref[1] = INFINITY;
    const StepResult<Cap> r = ctl.step(ref, l, nullptr);
    for (int i = 0; i < 2; ++i) {
      ASSERT_TRUE(std::isfinite(r.u[i])) << GetParam().what << " step " << k;
      ASSERT_GE(r.u[i], P.u_min[i]);
      ASSERT_LE(r.u[i], P.u_max[i]);
    }
    if (k % 7 == 0) {
      EXPECT_TRUE(r.flags & kBadSensor);
    }
    if (k % 11 == 0) {
      EXPECT_TRUE(r.flags & kBadReference);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, HostileParams,
    ::testing::Values(Hostile{"huge Q", [](Params<Cap>& P) { P.Q[0] = P.Q[1] = P.Q[2] = 1e12f; }},
                      Hostile{"zero Lambda", [](Params<Cap>& P) { P.Lambda[0] = P.Lambda[1] = 0.0f; }},
                      Hostile{"zero Q and Lambda",
                              [](Params<Cap>& P) {
                                for (float& q : P.Q) q = 0;
                                P.Lambda[0] = P.Lambda[1] = 0.0f;
                              }},
                      Hostile{"strong barrier inside limits",
                              [](Params<Cap>& P) {
                                P.s = 1e3f;
                                P.r = 0.5f;
                                P.b = 2.0f;
                              }},
                      Hostile{"fd with tiny eps",
                              [](Params<Cap>& P) {
                                P.mode = DerivMode::Fd;
                                P.eps = 1e-7f;
                              }},
                      Hostile{"fd with huge eps",
                              [](Params<Cap>& P) {
                                P.mode = DerivMode::Fd;
                                P.eps = 1e3f;
                              }},
                      Hostile{"many iterations", [](Params<Cap>& P) { P.nr_max_iter = 20; }}));

TEST(Controller, TracksAReachableSetpointWhenTheModelIsThePlant) {
  // The plant is the model itself, fed back as a measured output, so the
  // only error left is the solver's.
  auto o = test::random_model<Cap>(2, 2, 0, 2,
                                   {{LayerKind::Dense, 6, Activation::Tanh}, {LayerKind::Dense, 2, Activation::Linear}},
                                   5, 0.4f);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  Params<Cap> P;
  P.Q[0] = P.Q[1] = 100.0f;
  P.Lambda[0] = P.Lambda[1] = 1e-3f;
  P.s = 0.0f, P.r = 100.0f;
  for (int i = 0; i < 2; ++i) P.u_min[i] = -3.0f, P.u_max[i] = 3.0f;
  P.N = 3, P.Nc = 2, P.N1 = 1;
  P.feedback = Feedback::Measured;
  P.nr_max_iter = 5;
  static Controller<Cap> ctl;
  ASSERT_EQ(ctl.configure(&o.model, P), Status::Ok);
  const float u0[2] = {0, 0}, y_init[2] = {0, 0};
  ctl.reset(u0, y_init, nullptr);

  // A setpoint the plant can hold: its own steady state under a constant u*.
  static HorizonScratch<Cap, float> hs;
  const float ustar[2] = {0.5f, -0.4f};
  float x[8] = {};
  const InputLayout L{2, 2, 0, 2, 2};
  float y[2] = {0, 0};
  for (int k = 0; k < 400; ++k) {
    push_input(x, L, ustar);
    float yn[2];
    forward(o.model, x, yn, hs.fw);
    push_output(x, L, yn);
    if (k == 399) {
      ASSERT_NEAR(yn[0], y[0], 1e-5) << "model has no steady state";
    }
    y[0] = yn[0], y[1] = yn[1];
  }
  float ref[Cap::N * 2];
  for (int t = 0; t < 3; ++t) ref[2 * t] = y[0], ref[2 * t + 1] = y[1];

  // closed loop: plant = model, measured output fed back
  float xp[8] = {};
  float yp[2] = {0, 0};
  for (int k = 0; k < 300; ++k) {
    const StepResult<Cap> r = ctl.step(ref, nullptr, yp);
    push_input(xp, L, r.u);
    float yn[2];
    forward(o.model, xp, yn, hs.fw);
    push_output(xp, L, yn);
    yp[0] = yn[0], yp[1] = yn[1];
  }
  EXPECT_NEAR(yp[0], y[0], 1e-2 * (1 + std::abs(y[0])));
  EXPECT_NEAR(yp[1], y[1], 1e-2 * (1 + std::abs(y[1])));
}

TEST(Controller, RefusedParameterWriteKeepsTheRunningSet) {
  auto o = tendon_like(1);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  Params<Cap> P;
  P = test::shipped_params<Cap>("tendon");
  static Controller<Cap> ctl;
  ASSERT_EQ(ctl.configure(&o.model, P), Status::Ok);
  const float bad[3] = {1.0f, std::nanf(""), 2.0f};
  const ParamResult r = ctl.set_param(ParamId::Q, bad, 3);
  EXPECT_EQ(r.status, Status::NotFinite);
  EXPECT_EQ(r.index, 1);
  EXPECT_EQ(ctl.params().Q[1], P.Q[1]);
  const float nc[1] = {4.0f};  // Nc > N = 3
  EXPECT_EQ(ctl.set_param(ParamId::Nc, nc, 1).status, Status::Inconsistent);
  EXPECT_EQ(ctl.params().Nc, 3);
}

TEST(RigParams, ACapacityTooSmallForTheRigIsRefused) {
  Params<HaselCapacity> P;
  EXPECT_EQ(host::rig_params(test::shipped_rig_file("hasel"), P), Status::Ok);
  EXPECT_EQ(host::rig_params(test::shipped_rig_file("tendon"), P), Status::TooLarge);  // Nc = 3 > 1
}
