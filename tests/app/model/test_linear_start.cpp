// Networks that start as the linear model (app/model/linear_start.hpp): the
// embedding is exact, refused where it cannot be, and train starts every
// network that can hold it there and keeps nothing worse.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/model/error.hpp"
#include "app/model/excitation.hpp"
#include "app/model/linear_start.hpp"
#include "app/model/train.hpp"
#include "support/shipped_rigs.hpp"

using namespace nlsoft;
using namespace nlsoft::model;

namespace {

Eigen::MatrixXd random_rows(long rows, int cols, Random& rng) {
  Eigen::MatrixXd X(rows, cols);
  for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = rng.uniform(-1.0, 1.0);
  return X;
}

}  // namespace

// The network's output is the linear model's over the rows the shift was
// set on, through relu and linear hidden layers wider than n.
TEST(LinearStart, TheNetworkStartsAsTheLinearModel) {
  Random rng(7);
  const int p = 9, n = 3;
  const Eigen::MatrixXd X = random_rows(500, p, rng);
  Network linear(p, {{LayerKind::Dense, n, Activation::Linear}});
  linear.initialise(rng);
  for (double& t : linear.theta()) t += 0.2 * rng.gaussian();  // non-zero biases too
  Network net(p, {{LayerKind::Dense, 5, Activation::Relu}, {LayerKind::Dense, 4, Activation::Linear},
                  {LayerKind::Dense, n, Activation::Linear}});
  net.initialise(rng);
  embed_linear_model(net, linear, X);
  const Eigen::MatrixXd b = linear.predict(X);
  EXPECT_LT((net.predict(X) - b).cwiseAbs().maxCoeff(), 1e-12);
  // Not the linear model's output by chance: moving a weight of the first
  // layer moves the network's.
  net.theta()[0] += 0.1;
  EXPECT_GT((net.predict(X) - b).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(LinearStart, OnlyALinearOutputAfterDenseReluOrLinearLayersAtLeastNWideHoldsIt) {
  using L = std::vector<LayerSpec>;
  const LayerSpec out{LayerKind::Dense, 3, Activation::Linear};
  EXPECT_TRUE(holds_linear_model(L{{LayerKind::Dense, 5, Activation::Relu}, out}, 3));
  EXPECT_TRUE(holds_linear_model(L{{LayerKind::Dense, 3, Activation::Linear}, out}, 3));
  EXPECT_FALSE(holds_linear_model(L{{LayerKind::Dense, 5, Activation::Relu}, {LayerKind::Dense, 3, Activation::Tanh}}, 3));
  EXPECT_FALSE(holds_linear_model(L{{LayerKind::Dense, 2, Activation::Relu}, out}, 3));
  EXPECT_FALSE(holds_linear_model(L{{LayerKind::Dense, 5, Activation::Tanh}, out}, 3));
  EXPECT_FALSE(holds_linear_model(L{{LayerKind::Gru, 5, Activation::Tanh}, out}, 3));
  EXPECT_FALSE(holds_linear_model(L{{LayerKind::Dense, 5, Activation::Relu}, {LayerKind::Dense, 2, Activation::Linear}}, 3));
  // What cannot hold it is refused, not half-changed.
  Random rng(1);
  Network linear(4, {{LayerKind::Dense, 3, Activation::Linear}});
  for (const L& layers : {L{{LayerKind::Dense, 2, Activation::Relu}, out},
                          L{{LayerKind::Dense, 5, Activation::Relu}, {LayerKind::Dense, 3, Activation::Tanh}}}) {
    Network net(4, layers);
    net.initialise(rng);
    const std::vector<double> before = net.theta();
    EXPECT_THROW(embed_linear_model(net, linear, random_rows(10, 4, rng)), PipelineError);
    EXPECT_EQ(net.theta(), before);
  }
}

// hasel's shape starts every seed at the linear model (the same free run
// for each), and none ends worse on the rows that judge it; --start random
// keeps the one-step warm start from random weights, and a tanh output
// starts at random whatever --start says.
TEST(LinearStart, TrainStartsEveryNetworkThatHoldsItThereAndKeepsNothingWorse) {
  const PlantTarget t = test::shipped_target("hasel");
  const Series s = generate_excitation(PlantKind::Hasel, 6000, 2);
  TrainOptions o = default_options(t);
  ASSERT_EQ(o.layers.back().act, Activation::Linear);
  o.seeds = 2;
  o.sim.lbfgs_evals = 30;
  const TrainResult r = train(s, t, o);
  // Two seeds of the network, then the linear models it must beat (the
  // output-error model, ARX), which start from least squares.
  ASSERT_EQ(r.candidates.size(), 4u);
  for (size_t i = 0; i < 2; ++i) {
    const Candidate& c = r.candidates[i];
    EXPECT_TRUE(c.is_network());
    EXPECT_TRUE(c.linear_start);
    EXPECT_EQ(c.warm_free_run, r.candidates[0].warm_free_run);
    EXPECT_LE(c.val_free_run, c.warm_free_run);
  }
  EXPECT_FALSE(r.candidates[2].is_network());
  EXPECT_TRUE(r.candidates[3].arx);
  o.start = Start::Random;
  const TrainResult q = train(s, t, o);
  for (const Candidate& c : q.candidates) EXPECT_FALSE(c.linear_start);
  EXPECT_NE(q.candidates[0].warm_free_run, q.candidates[1].warm_free_run);  // each its own warm start
  o.start = Start::Linear;
  o.layers.back().act = Activation::Tanh;
  const TrainResult h = train(s, t, o);
  for (const Candidate& c : h.candidates) EXPECT_FALSE(c.linear_start);
}
