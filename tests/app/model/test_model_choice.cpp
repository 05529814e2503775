// Which model train keeps: never one that simulates the held-out rows worse
// than the simplest it tried (ARX on the same lags, the linear output-error
// model), the choice made on the rows the held-out table shows; and the
// history length searched on the data (app/model/lag_search.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "app/model/error.hpp"
#include "app/model/lag_search.hpp"
#include "app/model/model_fit.hpp"
#include "app/model/random.hpp"
#include "app/model/train.hpp"

using namespace nlsoft;
using namespace nlsoft::model;

namespace {

// y(k+1) = a1 y(k) + a2 y(k-1) + a3 y(k-2) + b u(k) + small noise, driven
// by a random staircase: order 1 (a2 = a3 = 0) or 3.
Series linear_system(long q, int order, uint64_t seed, double noise = 0.0) {
  Random rng(seed);
  Series s;
  s.resize(q, 1, 1, 0);
  double u = 0.0, y0 = 0.0, y1 = 0.0, y2 = 0.0;
  // Order 3: poles 0.9 and 0.6 +- 0.5i (stable, oscillating); order 1: 0.8.
  const double a1 = order == 3 ? 2.1 : 0.8, a2 = order == 3 ? -1.69 : 0.0, a3 = order == 3 ? 0.549 : 0.0;
  for (long k = 0; k < q; ++k) {
    s.time(k) = 0.01 * double(k);
    if (rng.uniform() < 0.15) u = rng.uniform(-1.0, 1.0);
    s.u(k, 0) = u;
    s.y(k, 0) = y0 + noise * rng.gaussian();
    const double next = a1 * y0 + a2 * y1 + a3 * y2 + 0.2 * u;
    y2 = y1, y1 = y0, y0 = next;
  }
  return s;
}

PlantTarget target_for(const Series& s) {
  PlantTarget t;
  t.name = "line";
  t.m = s.m, t.n = s.n, t.w = s.w;
  t.nd = t.dd = 2;
  t.u_lo = {-1.0};
  t.u_hi = {1.0};
  double lo = s.y(0, 0), hi = s.y(0, 0);
  for (long k = 0; k < s.rows(); ++k) lo = std::min(lo, s.y(k, 0)), hi = std::max(hi, s.y(k, 0));
  t.y_rest = {0.5 * (lo + hi)};
  t.y_span = {hi - lo};
  t.y_names = {"y"};
  t.y_unit = "V";
  t.horizon = 10;
  return t;
}

// Options under which a network cannot learn (one epoch from random
// weights, no simulation training): the linear models must win.
TrainOptions losing_network_options(const PlantTarget& t) {
  TrainOptions o = default_options(t);
  o.nd = o.dd = 1;
  o.start = Start::Random;
  o.epochs = 1;
  o.seeds = 1;
  o.sim.epochs = 0;
  o.sim.lbfgs_evals = 0;
  return o;
}

}  // namespace

// A tanh network trained one epoch from a random start cannot simulate a
// linear plant as well as least squares does: the linear model is kept,
// and the result names the network it beat.
TEST(ModelChoice, ANetworkThatLosesToTheLinearModelIsNotKept) {
  const Series s = linear_system(3000, 1, 7, 1e-3);
  const PlantTarget t = target_for(s);
  TrainOptions o = losing_network_options(t);
  o.layers = {{LayerKind::Dense, 8, Activation::Tanh}, {LayerKind::Dense, 1, Activation::Tanh}};
  o.alternatives.clear();
  const TrainResult r = train(s, t, o);
  ASSERT_LT(r.chosen, r.candidates.size());
  const Candidate& kept = r.candidates[r.chosen];
  EXPECT_FALSE(kept.is_network());
  EXPECT_EQ(r.model.shape.layer_count, 1);
  ASSERT_NE(r.beaten_network, size_t(-1));
  EXPECT_TRUE(r.candidates[r.beaten_network].is_network());
  EXPECT_LT(kept.held_out, r.candidates[r.beaten_network].held_out);
  // ARX and the output-error model were both tried.
  int arx = 0, oe = 0;
  for (const Candidate& c : r.candidates) arx += c.arx, oe += !c.arx && !c.is_network();
  EXPECT_EQ(arx, 1);
  EXPECT_EQ(oe, 1);
}

// The choice and the held-out table cannot disagree: the kept model's
// held-out free run is the best of all candidates, and it is the free-run
// RMSE the table (model_fit's first section) prints for it; the table's ARX
// column is no better.
TEST(ModelChoice, TheKeptModelIsTheBestOnTheHeldOutTable) {
  const Series s = linear_system(3000, 3, 11, 2e-3);
  const PlantTarget t = target_for(s);
  TrainOptions o = default_options(t);
  o.nd = o.dd = 3;
  o.seeds = 1;
  o.sim.lbfgs_evals = 20;
  const TrainResult r = train(s, t, o);
  const Candidate& kept = r.candidates[r.chosen];
  for (const Candidate& c : r.candidates) EXPECT_LE(kept.held_out, c.held_out) << describe_layers(c.layers);
  const ModelFit f = model_fit(r, t);
  ASSERT_FALSE(f.sections.empty());
  ASSERT_TRUE(f.sections[0].has_arx);
  const OutputFit& o0 = f.sections[0].outputs[0];
  ASSERT_EQ(kept.held_out_rmse.size(), 1u);
  EXPECT_NEAR(o0.free_run.rmse, kept.held_out_rmse[0], 1e-12 * std::max(1.0, o0.free_run.rmse));
  // ARX in the table is the double least squares; the candidate the float one.
  EXPECT_LE(o0.free_run.rmse, o0.arx_free_run.rmse * (1.0 + 1e-3));
}

// A third-order system needs three samples of history; a first-order one
// needs one: the search finds more lags for the system that needs them.
TEST(LagSearch, PicksMoreLagsForAThirdOrderSystemThanAFirstOrderOne) {
  const LagChoice first = search_lags({linear_system(4000, 1, 3, 1e-4)}, 8, 10, -1);
  const LagChoice third = search_lags({linear_system(4000, 3, 3, 1e-4)}, 8, 10, -1);
  EXPECT_EQ(first.tried.size(), 8u);
  EXPECT_EQ(first.lags, 1) << first.words();
  EXPECT_GE(third.lags, 3) << third.words();
  EXPECT_GT(third.lags, first.lags);
  EXPECT_NE(third.words().find("nd = dd = " + std::to_string(third.lags)), std::string::npos);
}

TEST(LagSearch, TheNetworkTriesLengthsDoublingFromTheLinearChoiceToTheCapacity) {
  EXPECT_EQ(probe_lengths(7, 32), (std::vector<int>{7, 14, 32}));
  EXPECT_EQ(probe_lengths(21, 32), (std::vector<int>{21, 32}));
  EXPECT_EQ(probe_lengths(1, 8), (std::vector<int>{1, 2, 4, 8}));
  EXPECT_TRUE(probe_lengths(32, 32).empty());
  EXPECT_TRUE(probe_lengths(0, 8).empty());
}

// y(k+1) = u(k-5)^2 - 1/3 with u uniform on [-1, 1]: no linear model
// predicts any of it (the square of a zero-mean input is uncorrelated with
// it), so ARX's free run is flat and stage 1 takes the shortest length;
// a network sees u(k-5) only with a history of 6 or more, and stage 2
// finds the length that holds it.
TEST(LagSearch, ANetworkFindsTheHistoryALinearModelCannotSee) {
  Random rng(11);
  Series s;
  const long q = 3000;
  s.resize(q, 1, 1, 0);
  std::vector<double> u(static_cast<size_t>(q), 0.0);
  for (long k = 0; k < q; ++k) {
    s.time(k) = 0.01 * double(k);
    u[size_t(k)] = rng.uniform(-1.0, 1.0);
    s.u(k, 0) = u[size_t(k)];
    s.y(k, 0) = k >= 6 ? u[size_t(k - 6)] * u[size_t(k - 6)] - 1.0 / 3.0 : 0.0;
  }
  PlantTarget t = target_for(s);
  TrainOptions o = default_options(t);
  const LagChoice arx = search_lags({s}, 8, o.folds, -1);
  EXPECT_LT(arx.lags, 6) << arx.words();
  std::vector<int> probed;
  const LagChoice c = probe_network_lags(arx, {s}, t, o, -1, 8, [&](int L, const std::string&) { probed.push_back(L); });
  EXPECT_EQ(probed, probe_lengths(arx.lags, 8));
  ASSERT_EQ(c.probed.size(), probed.size());
  EXPECT_EQ(c.arx_lags, arx.lags);
  EXPECT_EQ(c.lags, 8) << c.words();
  EXPECT_LT(c.probed.back().free_run, 0.5 * c.probed.front().free_run) << c.words();
  EXPECT_NE(c.words().find("which chose " + std::to_string(arx.lags)), std::string::npos) << c.words();
}

// The one-step objective trains no free run to judge lengths by: stage 1 stands.
TEST(LagSearch, TheOneStepObjectiveKeepsTheLinearChoice) {
  const Series s = linear_system(2000, 3, 5, 1e-4);
  const PlantTarget t = target_for(s);
  const LagChoice arx = search_lags({s}, 8, 10, -1);
  int probes = 0;
  const LagChoice c = probe_network_lags(arx, {s}, t, default_options(t, Objective::OneStep), -1, 8,
                                         [&](int, const std::string&) { ++probes; });
  EXPECT_EQ(probes, 0);
  EXPECT_EQ(c.lags, arx.lags);
  EXPECT_TRUE(c.probed.empty());
}

TEST(LagSearch, ADataSetTooShortForAnyLengthIsRefused) {
  EXPECT_THROW(search_lags({linear_system(8, 1, 3)}, 4, 10, -1), PipelineError);
}

// A rig file's [model] shape is what its images are built for: where the
// linear model wins, it is carried in that shape when the shape can hold it
// (relu hidden units, a linear output), and the kept model simulates the
// held-out rows as the linear one does; where it cannot (a tanh output),
// the best network of the shape is kept and the result says the linear
// model won.
TEST(ModelChoice, ARigsOwnShapeCarriesTheLinearModelOrKeepsItsBestNetwork) {
  const Series s = linear_system(3000, 1, 7, 1e-3);
  PlantTarget t = target_for(s);
  t.layers = {{LayerKind::Dense, 8, Activation::Relu}, {LayerKind::Dense, 1, Activation::Linear}};
  TrainOptions o = losing_network_options(t);
  ASSERT_TRUE(o.keep_shape);
  const TrainResult r = train(s, t, o);
  ASSERT_NE(r.carried_linear, size_t(-1));
  EXPECT_EQ(r.model.shape.layer_count, 2);
  const Candidate &kept = r.candidates[r.chosen], &linear = r.candidates[r.carried_linear];
  EXPECT_FALSE(linear.is_network());
  EXPECT_NEAR(kept.held_out, linear.held_out, 1e-4 * linear.held_out);

  t.layers = {{LayerKind::Dense, 8, Activation::Relu}, {LayerKind::Dense, 1, Activation::Tanh}};
  const TrainResult h = train(s, t, losing_network_options(t));
  ASSERT_NE(h.linear_not_carried, size_t(-1));
  EXPECT_TRUE(h.candidates[h.chosen].is_network());
  EXPECT_EQ(h.model.shape.layer_count, 2);
  EXPECT_LT(h.candidates[h.linear_not_carried].held_out, h.candidates[h.chosen].held_out);
}
