// The fit's figures against hand-computed ones: RMSE, nRMSE of the span and
// MATLAB compare's fit % = 100 (1 - |y - yhat| / |y - mean(y)|); the ARX
// baseline's least squares recovers a difference equation exactly and its
// free run feeds back its own outputs; an older console's fit still reads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <unistd.h>

#include "app/model/arx.hpp"
#include "app/model/fit_scores.hpp"
#include "app/model/model_fit.hpp"
#include "app/model/model_section.hpp"
#include "app/model/model_store.hpp"

namespace nlsoft::model {
namespace {

TEST(FitScores, FitPercentIsMatlabComparesOnAHandComputedCase) {
  Eigen::MatrixXd y(4, 1), yhat(4, 1);
  y << 1, 2, 3, 4;
  yhat << 1, 2, 3, 5;
  // |y - yhat| = 1; mean 2.5, |y - mean| = sqrt(2.25 + 0.25 + 0.25 + 2.25) = sqrt(5).
  const std::vector<Score> s = score(y, yhat, {10.0});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_NEAR(s[0].fit, 100.0 * (1.0 - 1.0 / std::sqrt(5.0)), 1e-12);  // 55.28 %
  EXPECT_NEAR(s[0].rmse, 0.5, 1e-12);                                  // sqrt(1 / 4)
  EXPECT_NEAR(s[0].nrmse, 0.05, 1e-12);                                // of the span 10
  // The mean itself fits 0 %; a constant output has no fit at all.
  yhat.setConstant(2.5);
  EXPECT_NEAR(score(y, yhat, {10.0})[0].fit, 0.0, 1e-12);
  y.setConstant(1.0);
  EXPECT_TRUE(std::isnan(score(y, yhat, {10.0})[0].fit));
}

// q rows of y(k+1) = 0.5 y(k) - 0.2 y(k-1) + 2 u(k) + 0.3 u(k-1) + 1.
Series difference_equation(long q) {
  Series s;
  s.resize(q, 1, 1, 0);
  double y1 = 0, y0 = 0, u1 = 0;
  for (long k = 0; k < q; ++k) {
    s.time(k) = 0.01 * double(k);
    s.u(k, 0) = std::sin(0.37 * double(k)) + ((k / 13) % 2 ? 0.5 : -0.5);
    s.y(k, 0) = y0;
    const double next = 0.5 * y0 - 0.2 * y1 + 2.0 * s.u(k, 0) + 0.3 * u1 + 1.0;
    y1 = y0, y0 = next, u1 = s.u(k, 0);
  }
  return s;
}

// The difference equation above: the baseline's coefficients are these,
// and its free run from the first measured history reproduces y (fit 100 %).
TEST(FitScores, TheArxBaselineRecoversADifferenceEquation) {
  const Dataset d = build_dataset(difference_equation(400), 2, 2);
  const ArxModel a = fit_arx(d, d.pieces);
  // Input order: u(k), u(k-1), y(k), y(k-1), bias.
  const double want[] = {2.0, 0.3, 0.5, -0.2, 1.0};
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(a.theta(i, 0), want[i], 1e-9) << i;
  const Simulation sim = simulate_arx(a, d, d.pieces);
  const std::vector<Score> free = score(measured(d, d.pieces), sim.free_run, {});
  EXPECT_NEAR(free[0].fit, 100.0, 1e-6);
  // Kept as JSON in the model file and read back the same.
  const ArxModel back = arx_from_json(arx_to_json(a), "test");
  EXPECT_EQ(back.theta, a.theta);
  // A free run that is fed its own outputs drifts where one-step does not:
  // a baseline off by a little in its pole shows it.
  ArxModel off = a;
  off.theta(2, 0) += 0.05;
  const Simulation worse = simulate_arx(off, d, d.pieces);
  const Eigen::MatrixXd y = measured(d, d.pieces);
  EXPECT_LT(score(y, worse.free_run, {})[0].fit, score(y, worse.one_step, {})[0].fit);
}

// k steps ahead (the controller's horizon, paper eq. 3): from the measured
// history k - 1 rows back and the predictor's own outputs since. With k = 1
// that is one-step; with k past the data's length every row starts from
// the first, which is the free run; in between, an off baseline errs more
// than one step ahead, and each row is the one worked out by hand.
TEST(FitScores, KStepsAheadStartsFromTheHistoryKMinusOneRowsBack) {
  const long q = 300;
  const Dataset d = build_dataset(difference_equation(q), 2, 2);
  ArxModel off = fit_arx(d, d.pieces);
  off.theta(2, 0) += 0.05;  // its pole a little off: errors grow as it feeds itself
  const Eigen::MatrixXd y = measured(d, d.pieces);
  EXPECT_EQ(simulate_arx(off, d, d.pieces, 1).k_step.rows(), 0);  // k = 1 is one-step: not repeated
  const Simulation far = simulate_arx(off, d, d.pieces, int(q) + 10);
  EXPECT_EQ(far.k_step, far.free_run);
  const double one = score(y, far.one_step, {})[0].rmse;
  for (int k : {2, 3, 5, 10}) EXPECT_GT(score(y, simulate_arx(off, d, d.pieces, k).k_step, {})[0].rmse, one) << k;
  // The row k steps ahead of its start, by hand: from row 10's history, 3 steps.
  const Simulation three = simulate_arx(off, d, d.pieces, 3);
  Eigen::VectorXd x = d.X.row(10).transpose();
  double yhat[1];
  for (long r = 10; r <= 12; ++r) {
    const Eigen::VectorXd row = d.X.row(r).transpose();
    for (int i = 0; i < d.layout.p(); ++i)
      if (i < d.layout.y_begin() || i >= d.layout.y_begin() + d.layout.dd * d.layout.n) x(i) = row(i);
    off.predict(x.data(), yhat);
    x(d.layout.y_begin() + 1) = x(d.layout.y_begin());
    x(d.layout.y_begin()) = yhat[0];
  }
  EXPECT_NEAR(three.k_step(12, 0), yhat[0], 1e-12);
}

TEST(FitScores, AnOlderConsolesFitStillReads) {
  const ModelFit f = fit_from_json(
      R"j({"rig":"msd","held_out":"the last 1/11 of the run (90 rows)","rows":90,)j"
      R"j("outputs":[{"name":"x","span":0.2,"one_step_nrmse":0.01,"free_run_nrmse":0.02}]})j",
      "old.nlsm");
  ASSERT_EQ(f.sections.size(), 1u);
  EXPECT_EQ(f.sections[0].title, "held-out data of rig msd: the last 1/11 of the run (90 rows)");
  EXPECT_FALSE(f.sections[0].has_arx);
  EXPECT_NEAR(f.sections[0].outputs[0].free_run.nrmse, 0.02, 1e-15);
  EXPECT_NE(fit_table(f).find("no ARX baseline"), std::string::npos);
}

// The largest model the console holds (p = 88 inputs, n = 6 outputs, 7950
// weights) with a fit and its ARX baseline, (88 + 1) x 6 coefficients,
// after it: the file is larger than the largest model alone, and still
// reads back, the same model and fit.
TEST(FitScores, TheLargestModelWithItsFitAndBaselineReadsBack) {
  ModelFile f;
  Model<HostCapacity>& M = f.shape;
  M.m = 8, M.n = 6, M.w = 32, M.nd = 4, M.dd = 4;
  const int sizes[] = {88, 48, 48, 24, 6};
  M.layer_count = 4;
  size_t weights = 0;
  for (int i = 0; i < 4; ++i) {
    M.layer[i].kind = LayerKind::Dense;
    M.layer[i].act = i < 3 ? Activation::Relu : Activation::Linear;
    M.layer[i].in = uint16_t(sizes[i]);
    M.layer[i].out = uint16_t(sizes[i + 1]);
    weights += layer_weight_count(M.layer[i]);
  }
  f.params.assign(weights + 2 * 88 + 2 * 6, 0.25f);
  finalize(f);
  ArxModel a;
  a.layout = InputLayout{8, 6, 32, 4, 4};
  a.theta = Eigen::MatrixXd::Random(89, 6) / 3.0;
  ModelFit fit;
  fit.rig = "big";
  fit.held_out = "the last 1/11 of the run (100 rows)";
  fit.arx = arx_to_json(a);
  FitSection sec;
  sec.title = "held-out data of rig big: " + fit.held_out;
  sec.rows = 100;
  sec.has_arx = true;
  for (int j = 0; j < 6; ++j) sec.outputs.push_back({"y" + std::to_string(j), 1.0, {}, {}, {}, {}, {}, {}});
  fit.sections = {sec, sec};
  f.fit = fit_to_json(fit);
  const std::string path = ::testing::TempDir() + "/largest_" + std::to_string(::getpid()) + ".nlsm";
  save_model_file(path, f);
  const std::vector<uint8_t> bytes = encode_model_file(f);
  EXPECT_GT(bytes.size(), model_file_max<HostCapacity>());
  EXPECT_LE(bytes.size(), model_file_with_sections_max());
  const ModelFile back = load_model_file(path);
  std::remove(path.c_str());
  EXPECT_EQ(back.shape.hash, f.shape.hash);
  EXPECT_EQ(back.fit, f.fit);
  EXPECT_EQ(arx_from_json(fit_from_json(back.fit, path).arx, path).theta, a.theta);
}

// msd's 1 kHz identification run: ARX in double simulated the held-out rows
// at 7.1e-07 m, the kept model (float, as the firmware runs it) at 3.1e-04 m
// and ARX in float at 0.024 m. train says why, with the three figures; where
// the double ARX is not far better, it says nothing.
TEST(FitText, AFarBetterDoubleArxIsExplainedAsFloatRounding) {
  TrainResult r;
  r.objective = Objective::Simulation;
  Candidate kept, arx;
  kept.layers = {{LayerKind::Dense, 1, Activation::Linear}};
  kept.held_out_rmse = {3.058e-4};
  arx.arx = true;
  arx.held_out_rmse = {0.02425};
  r.candidates = {kept, arx};
  r.chosen = 0;
  ModelFit fit;
  FitSection s;
  s.has_arx = true;
  OutputFit o;
  o.name = "x";
  o.span = 2.0;
  o.arx_free_run.rmse = 7.126e-7;
  s.outputs = {o};
  fit.sections = {s};
  const std::string w = float_gap_words(r, fit, "m");
  EXPECT_NE(w.find("x: ARX 7.126e-07 m in double, 0.02425 m in float, the kept model 0.0003058 m"), std::string::npos)
      << w;
  fit.sections[0].outputs[0].arx_free_run.rmse = 2e-4;  // not twice better: nothing to explain
  EXPECT_EQ(float_gap_words(r, fit, "m"), "");
  fit.sections[0].outputs[0].arx_free_run.rmse = 7.126e-7;
  fit.sections[0].outputs[0].span = 1e3;  // the kept model within 1e-5 of the span: rounding on both sides
  EXPECT_EQ(float_gap_words(r, fit, "m"), "");
  fit.sections[0].outputs[0].span = 2.0;
  fit.sections[0].has_arx = false;
  fit.sections[0].outputs[0].arx_free_run.rmse = 7.126e-7;
  EXPECT_EQ(float_gap_words(r, fit, "m"), "");
}

}  // namespace
}  // namespace nlsoft::model
