// Backpropagation, training, repeatability, and the guarantee that the
// exported model file computes what the trainer trained.
#include <gtest/gtest.h>

#include <cmath>

#include "app/model/error.hpp"
#include "app/model/excitation.hpp"
#include "app/model/network.hpp"
#include "app/model/train.hpp"
#include "shared/forward.hpp"
#include "support/shipped_rigs.hpp"

using namespace nlsoft;
using namespace nlsoft::model;

namespace {

// Central-difference check of the analytic gradient of L = sum(out * R).
void check_gradient(const std::vector<LayerSpec>& layers, int inputs, uint64_t seed) {
  Network net(inputs, layers);
  Random rng(seed);
  net.initialise(rng);
  for (double& t : net.theta()) t += 0.3 * rng.gaussian();  // biases non-zero too
  Eigen::MatrixXd X(7, inputs), R(7, net.outputs());
  for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = rng.uniform(-1.0, 1.0);
  for (Eigen::Index i = 0; i < R.size(); ++i) R.data()[i] = rng.uniform(-1.0, 1.0);
  Network::Cache c;
  net.forward(X, c);
  std::vector<double> grad;
  net.backward(c, R, grad);
  const double h = 1e-6;
  for (size_t k = 0; k < net.param_count(); ++k) {
    const double keep = net.theta()[k];
    net.theta()[k] = keep + h;
    const double up = (net.predict(X).array() * R.array()).sum();
    net.theta()[k] = keep - h;
    const double down = (net.predict(X).array() * R.array()).sum();
    net.theta()[k] = keep;
    EXPECT_NEAR(grad[k], (up - down) / (2 * h), 1e-6 * std::max(1.0, std::abs(grad[k]))) << "parameter " << k;
  }
}

// A plant-shaped series whose next output is a known smooth function of
// the input vector: y(k+1) = 0.4 tanh(u(k)/800) + 0.5 y(k) - 0.2 y(k-1).
Series known_function(long q, uint64_t seed) {
  Random rng(seed);
  Series s;
  s.resize(q, 1, 1, 0);
  double u = 0.0;
  for (long k = 0; k < q; ++k) {
    s.time(k) = 1e-3 * double(k);
    if (rng.uniform() < 0.1) u = rng.uniform(-2000.0, 2000.0);
    s.u(k, 0) = u;
    s.y(k, 0) = k < 2 ? 0.0 : 0.4 * std::tanh(s.u(k - 1, 0) / 800.0) + 0.5 * s.y(k - 1, 0) - 0.2 * s.y(k - 2, 0);
  }
  return s;
}

// Largest |trainer - firmware forward| over the test rows, relative to max(1, |y|).
double export_mismatch(const TrainResult& r, const Series& s, int nd) {
  const Dataset d = build_dataset(s, nd, nd);
  const Eigen::MatrixXd ref = r.trained.predict(d.X);
  const Model<HostCapacity> M = r.model.view();
  ForwardScratch<HostCapacity, float> scratch;
  float x[Dims<HostCapacity>::p], y[HostCapacity::n];
  double worst = 0.0;
  for (long row = 0; row < d.rows(); row += 7) {
    for (int i = 0; i < M.p(); ++i) x[i] = float(d.X(row, i));
    forward(M, x, y, scratch);
    for (int j = 0; j < M.n; ++j)
      worst = std::max(worst, std::abs(double(y[j]) - ref(row, j)) / std::max(1.0, std::abs(ref(row, j))));
  }
  return worst;
}

}  // namespace

TEST(Network, DenseGradientMatchesFiniteDifferences) {
  check_gradient({{LayerKind::Dense, 4, Activation::Tanh}, {LayerKind::Dense, 3, Activation::Sigmoid},
                  {LayerKind::Dense, 2, Activation::Linear}},
                 5, 1);
}

TEST(Network, GruGradientMatchesFiniteDifferences) {
  check_gradient({{LayerKind::Gru, 3, Activation::Tanh, Activation::Sigmoid, true},
                  {LayerKind::Dense, 2, Activation::Tanh}},
                 4, 2);
  check_gradient({{LayerKind::Gru, 3, Activation::Tanh, Activation::Sigmoid, false},
                  {LayerKind::Dense, 2, Activation::Linear}},
                 4, 3);
}

TEST(Train, LearnsAKnownFunctionRepeatably) {
  const Series s = known_function(6000, 4);
  TrainOptions o;
  o.layers = {{LayerKind::Dense, 8, Activation::Tanh}, {LayerKind::Dense, 1, Activation::Linear}};
  o.epochs = 150;
  o.seed = 11;
  const TrainResult a = train(s, test::shipped_target("msd"), o);
  const double var = (s.y.array() - s.y.mean()).square().mean();
  EXPECT_LT(a.test.mse[0], 1e-3 * var) << "variance " << var;
  const TrainResult b = train(s, test::shipped_target("msd"), o);
  EXPECT_EQ(a.model.params, b.model.params);  // bit for bit
  // Another seed starts elsewhere: its weights differ from the first
  // epochs on, so a few epochs show it (the whole run cost a quarter of the
  // test, 20 s under ASan).
  o.seed = 12;
  o.epochs = 5;
  const TrainResult c = train(s, test::shipped_target("msd"), o);
  EXPECT_NE(a.model.params, c.model.params);
  o.loss = Loss::Huber;
  o.seed = 11;
  o.epochs = 150;
  const TrainResult h = train(s, test::shipped_target("msd"), o);
  EXPECT_LT(h.test.mse[0], 1e-2 * var);
}

TEST(Train, ExportedDenseModelEqualsTrainerForward) {
  const Series s = generate_excitation(PlantKind::Hasel, 4000, 1);
  TrainOptions o = default_options(test::shipped_target("hasel"), Objective::OneStep);
  o.epochs = 3;
  const TrainResult r = train(s, test::shipped_target("hasel"), o);
  EXPECT_LT(export_mismatch(r, s, 2), 1e-5);
  o.residual = true;
  o.layers[1].act = Activation::Sigmoid;
  const TrainResult rr = train(s, test::shipped_target("hasel"), o);
  EXPECT_TRUE(rr.model.shape.residual);
  EXPECT_LT(export_mismatch(rr, s, 2), 1e-5);
}

TEST(Train, ExportedGruModelEqualsTrainerForward) {
  const Series s = generate_excitation(PlantKind::Tendon, 4000, 1);
  TrainOptions o = default_options(test::shipped_target("tendon"), Objective::OneStep);
  o.epochs = 3;
  for (bool reset_after : {true, false}) {
    o.layers[0].reset_after = reset_after;
    o.layers[0].rec_act = reset_after ? Activation::Sigmoid : Activation::HardSigmoid;
    const TrainResult r = train(s, test::shipped_target("tendon"), o);
    EXPECT_EQ(r.model.shape.layer[0].kind, LayerKind::Gru);
    EXPECT_LT(export_mismatch(r, s, 2), 1e-5) << "reset_after " << reset_after;
  }
}

TEST(Train, LinearModelIsExactOnTheMassSpringDamper) {
  // The msd is linear: its ZOH discretisation is exactly an ARX(2,2) model,
  // so the least-squares fit must be near float precision.
  const Series s = generate_excitation(PlantKind::Msd, 20000, 3);
  const TrainResult r = train(s, test::shipped_target("msd"), default_options(test::shipped_target("msd")));
  EXPECT_EQ(r.epochs_run, 0);
  EXPECT_LT(r.test.mse[0], 1e-10);
  EXPECT_LT(export_mismatch(r, s, 2), 1e-5);
}

// The input limits and the outputs' centre come from the rig (the target a
// rig file makes), not from a plant simulated to its rest: a rig whose
// outputs range over [10, 30] is centred on 20, whatever the data.
TEST(Train, LimitsAndCentreComeFromTheRigNotASimulatedPlant) {
  const Series s = generate_excitation(PlantKind::Msd, 2000, 1);
  PlantTarget t = test::shipped_target("msd");
  t.plant = TargetPlant::Named;  // a simulated plant stands by, and is not asked
  t.u_lo = {-4000.0};
  t.u_hi = {6000.0};
  t.y_rest = {20.0};
  TrainOptions o = default_options(t);
  o.residual = false;
  const TrainResult r = train(s, t, o);
  const int p = r.model.shape.p();
  // in_offset[p], in_scale[p], out_offset[n], out_scale[n], then the weights
  EXPECT_EQ(r.model.params[size_t(2 * p)], 20.0f);
  EXPECT_EQ(r.model.params[0], 1000.0f);               // u's middle of [-4000, 6000]
  EXPECT_EQ(r.model.params[size_t(p)], 1.0f / 10000.0f);  // its span
}

// --nd/--dd: the lags the rows are built with and the model file records.
TEST(Train, LagsOtherThanTheRigsAreTrainedAndRecorded) {
  const Series s = generate_excitation(PlantKind::Msd, 3000, 1);
  TrainOptions o = default_options(test::shipped_target("msd"));
  o.nd = 3;
  o.dd = 4;
  const TrainResult r = train(s, test::shipped_target("msd"), o);
  EXPECT_EQ(r.model.shape.nd, 3);
  EXPECT_EQ(r.model.shape.dd, 4);
  EXPECT_EQ(r.model.shape.p(), 3 * 1 + 4 * 1 + 0);
  EXPECT_LT(r.test.mse[0], 1e-9);
}

TEST(Train, RefusesMismatchedData) {
  const Series s = generate_excitation(PlantKind::Tendon, 500, 1);
  EXPECT_THROW(train(s, test::shipped_target("hasel"), default_options(test::shipped_target("hasel"))), PipelineError);
  TrainOptions o = default_options(test::shipped_target("tendon"));
  o.layers.back().units = 2;
  EXPECT_THROW(train(s, test::shipped_target("tendon"), o), PipelineError);
}

TEST(ModelStore, SaveLoadRoundTripAndAtomicity) {
  const Series s = generate_excitation(PlantKind::Msd, 2000, 1);
  TrainResult r = train(s, test::shipped_target("msd"), default_options(test::shipped_target("msd")));
  const std::string path = ::testing::TempDir() + "/store_test.nlsm";
  save_model_file(path, r.model);
  const ModelFile back = load_model_file(path);
  EXPECT_EQ(back.params, r.model.params);
  EXPECT_EQ(back.platform, 0);  // rigs/msd.toml info_platform
  EXPECT_EQ(back.shape.hash, r.model.shape.hash);
  // a model that cannot be written leaves the old file alone
  ModelFile bad = r.model;
  bad.params[0] = NAN;
  EXPECT_THROW(save_model_file(path, bad), PipelineError);
  EXPECT_EQ(load_model_file(path).params, r.model.params);
}

// Two inputs that differ by 1e-10 (a prbs run's inputs and lags come close):
// the exact least-squares weights on them reach the millions and cancel in
// double only. The model the firmware runs, in float, must predict as the
// double fit does, to the noise.
TEST(Train, ALeastSquaresLayerStaysExactInFloatOnNearlyDependentColumns) {
  Random rng(5);
  Series s;
  const long q = 4000;
  s.resize(q, 2, 1, 0);
  double u = 0.0;
  const double noise = 1e-3;
  for (long k = 0; k < q; ++k) {
    s.time(k) = 0.01 * double(k);
    if (rng.uniform() < 0.05) u = rng.uniform() < 0.5 ? -0.5 : 0.5;
    s.u(k, 0) = u;
    s.u(k, 1) = u + 1e-10 * rng.gaussian();
    s.y(k, 0) = k == 0 ? 0.0 : 0.5 * s.y(k - 1, 0) + 0.3 * s.u(k - 1, 0) + noise * rng.gaussian();
  }
  PlantTarget t;
  t.name = "pair";
  t.m = 2, t.n = 1, t.w = 0, t.nd = 2, t.dd = 2;
  t.u_lo = {-1.0, -1.0};
  t.u_hi = {1.0, 1.0};
  t.y_rest = {0.0};
  t.y_span = {2.0};
  TrainOptions o;
  o.layers = {{LayerKind::Dense, 1, Activation::Linear}};
  o.objective = Objective::OneStep;
  o.nd = o.dd = 2;
  const TrainResult r = train(s, t, o);
  EXPECT_LT(r.test.mse[0], 2.0 * noise * noise) << "one-step RMSE " << std::sqrt(r.test.mse[0]);
  double largest = 0.0;
  for (double w : r.trained.net.theta()) largest = std::max(largest, std::abs(w));
  EXPECT_LT(largest, 1e4);
}
