// Keras HDF5 import: files written here with known weights, outputs checked
// against Keras' formulas computed independently in double.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "app/model/error.hpp"
#include "app/model/keras_import.hpp"
#include "app/model/model_store.hpp"
#include "cli_runner.hpp"
#include "h5_writer.hpp"
#include "shared/forward.hpp"
#include "shared/platform_id.hpp"

using namespace nlsoft;
using namespace nlsoft::model;
using nlsoft::test::H5Writer;
using nlsoft::test::run_cli;

namespace {

std::vector<float> values(size_t n, double seed) {
  std::vector<float> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = float(0.6 * std::sin(1.37 * double(i) + seed));
  return v;
}

double sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }
double hard_sigmoid(double x) { return std::min(1.0, std::max(0.0, 0.2 * x + 0.5)); }

// x W + b with W stored [in][out] (Keras layout)
std::vector<double> affine(const std::vector<double>& x, const std::vector<float>& W, const std::vector<float>* b,
                           size_t out, size_t bias_offset = 0) {
  std::vector<double> y(out, 0.0);
  for (size_t j = 0; j < out; ++j) {
    y[j] = b ? double((*b)[bias_offset + j]) : 0.0;
    for (size_t i = 0; i < x.size(); ++i) y[j] += x[i] * double(W[i * out + j]);
  }
  return y;
}

std::vector<double> input(size_t p, int row) {
  std::vector<double> x(p);
  for (size_t i = 0; i < p; ++i) x[i] = std::cos(0.7 * double(i) + 1.9 * row);
  return x;
}

std::vector<double> run_model(const std::string& path, const std::vector<double>& x) {
  const ModelFile f = load_model_file(path);
  const Model<HostCapacity> M = f.view();
  ForwardScratch<HostCapacity, float> s;
  float xf[64], y[8];
  for (size_t i = 0; i < x.size(); ++i) xf[i] = float(x[i]);
  forward(M, xf, y, s);
  return std::vector<double>(y, y + M.n);
}

void expect_close(const std::vector<double>& got, const std::vector<double>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t j = 0; j < got.size(); ++j)
    EXPECT_NEAR(got[j], want[j], 1e-5 * std::max(1.0, std::abs(want[j]))) << "output " << j;
}

std::string tmp(const std::string& name) { return ::testing::TempDir() + "/" + name; }

// TF 2.x layout: config {"layers": [...]}, names like "dense/kernel:0".
TEST(KerasImport, DenseWithDropout) {
  const std::string h5 = tmp("dense.h5");
  const auto W0 = values(4 * 3, 1), b0 = values(3, 2), W1 = values(3 * 1, 3), b1 = values(1, 4);
  {
    H5Writer w(h5);
    ASSERT_TRUE(w.ok());
    w.config(R"({"class_name": "Sequential", "config": {"name": "sequential", "layers": [
      {"class_name": "InputLayer", "config": {"batch_input_shape": [null, 4], "dtype": "float32", "name": "input_1"}},
      {"class_name": "Dense", "config": {"name": "dense", "units": 3, "activation": "relu", "use_bias": true}},
      {"class_name": "Dropout", "config": {"name": "dropout", "rate": 0.2}},
      {"class_name": "Dense", "config": {"name": "dense_1", "units": 1, "activation": "linear", "use_bias": true}}]}})",
             true);
    w.layer("dense", {"dense/kernel:0", "dense/bias:0"});
    w.array("dense", "dense/kernel:0", {4, 3}, W0);
    w.array("dense", "dense/bias:0", {3}, b0);
    w.layer("dropout", {});
    w.layer("dense_1", {"dense_1/kernel:0", "dense_1/bias:0"});
    w.array("dense_1", "dense_1/kernel:0", {3, 1}, W1);
    w.array("dense_1", "dense_1/bias:0", {1}, b1);
  }
  const std::string out = tmp("dense.nlsm");
  const auto r = run_cli("model import " + h5 + " --out " + out + " --rig msd");  // p = 4: msd's dims
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(load_model_file(out).platform, uint8_t(PlatformId::Msd));
  for (int row = 0; row < 5; ++row) {
    const auto x = input(4, row);
    auto h = affine(x, W0, &b0, 3);
    for (double& v : h) v = std::max(0.0, v);
    expect_close(run_model(out, x), affine(h, W1, &b1, 1));
  }
}

// TF 2.x GRU: reset_after = true, sigmoid gates, bias [2][3u], weights nested
// under the cell: "gru/gru_cell/kernel:0".
TEST(KerasImport, GruResetAfterSigmoid) {
  const std::string h5 = tmp("gru_ra.h5");
  const size_t p = 8, u = 3;
  const auto K = values(p * 3 * u, 5), R = values(u * 3 * u, 6), B = values(2 * 3 * u, 7);
  const auto W1 = values(u * 3, 8), b1 = values(3, 9);
  {
    H5Writer w(h5);
    w.config(R"({"class_name": "Sequential", "config": {"name": "s", "layers": [
      {"class_name": "InputLayer", "config": {"batch_input_shape": [null, 1, 8], "name": "in"}},
      {"class_name": "GRU", "config": {"name": "gru", "units": 3, "activation": "tanh",
        "recurrent_activation": "sigmoid", "use_bias": true, "reset_after": true, "return_sequences": false}},
      {"class_name": "Dense", "config": {"name": "dense", "units": 3, "activation": "tanh"}}]}})",
             true);
    w.layer("gru", {"gru/gru_cell/kernel:0", "gru/gru_cell/recurrent_kernel:0", "gru/gru_cell/bias:0"});
    w.array("gru", "gru/gru_cell/kernel:0", {p, 3 * u}, K);
    w.array("gru", "gru/gru_cell/recurrent_kernel:0", {u, 3 * u}, R);
    w.array("gru", "gru/gru_cell/bias:0", {2, 3 * u}, B);
    w.layer("dense", {"dense/kernel:0", "dense/bias:0"});
    w.array("dense", "dense/kernel:0", {u, 3}, W1);
    w.array("dense", "dense/bias:0", {3}, b1);
  }
  const std::string out = tmp("gru_ra.nlsm");
  const auto r = run_cli("model import " + h5 + " --out " + out + " --dims 1,3,0,2,2");
  ASSERT_EQ(r.code, 0) << r.output;
  for (int row = 0; row < 5; ++row) {
    const auto x = input(p, row);
    const auto g = affine(x, K, &B, 3 * u);  // input bias B[0]
    std::vector<double> h(u);
    for (size_t j = 0; j < u; ++j) {
      // zero state: the recurrent kernel meets h = 0, only the recurrent bias B[1] remains
      const double z = sigmoid(g[j] + double(B[3 * u + j]));
      const double rr = sigmoid(g[u + j] + double(B[3 * u + u + j]));
      const double hh = std::tanh(g[2 * u + j] + rr * double(B[3 * u + 2 * u + j]));
      h[j] = (1 - z) * hh;
    }
    auto y = affine(h, W1, &b1, 3);
    for (double& v : y) v = std::tanh(v);
    expect_close(run_model(out, x), y);
  }
}

// Keras 2.2 layout: the config is the bare layer list, fixed-length strings,
// reset_after absent (false), hard_sigmoid gates, a bias-free Dense.
TEST(KerasImport, Keras22GruHardSigmoid) {
  const std::string h5 = tmp("gru_22.h5");
  const size_t p = 8, u = 4;
  const auto K = values(p * 3 * u, 10), R = values(u * 3 * u, 11), B = values(3 * u, 12);
  const auto W1 = values(u * 3, 13);
  {
    H5Writer w(h5);
    w.config(R"({"class_name": "Sequential", "config": [
      {"class_name": "GRU", "config": {"name": "gru_1", "units": 4, "activation": "tanh",
        "recurrent_activation": "hard_sigmoid", "use_bias": true, "batch_input_shape": [null, 1, 8]}},
      {"class_name": "Flatten", "config": {"name": "flatten_1"}},
      {"class_name": "Dense", "config": {"name": "dense_1", "units": 3, "activation": "linear", "use_bias": false}}]})",
             false);
    w.layer("gru_1", {"gru_1/kernel:0", "gru_1/recurrent_kernel:0", "gru_1/bias:0"});
    w.array("gru_1", "gru_1/kernel:0", {p, 3 * u}, K);
    w.array("gru_1", "gru_1/recurrent_kernel:0", {u, 3 * u}, R);
    w.array("gru_1", "gru_1/bias:0", {3 * u}, B);
    w.layer("flatten_1", {});
    w.layer("dense_1", {"dense_1/kernel:0"});
    w.array("dense_1", "dense_1/kernel:0", {u, 3}, W1);
  }
  const std::string out = tmp("gru_22.nlsm");
  const auto r = run_cli("model import " + h5 + " --out " + out + " --dims 1,3,0,2,2");
  ASSERT_EQ(r.code, 0) << r.output;
  const ModelFile f = load_model_file(out);
  EXPECT_FALSE(f.shape.layer[0].reset_after);
  EXPECT_EQ(f.shape.layer[0].rec_act, Activation::HardSigmoid);
  for (int row = 0; row < 5; ++row) {
    const auto x = input(p, row);
    const auto g = affine(x, K, &B, 3 * u);
    std::vector<double> h(u);
    for (size_t j = 0; j < u; ++j) {
      const double z = hard_sigmoid(g[j]);
      h[j] = (1 - z) * std::tanh(g[2 * u + j]);  // r multiplies the zero state only
    }
    expect_close(run_model(out, x), affine(h, W1, nullptr, 3));
  }
}

TEST(KerasImport, NormalisationFromJson) {
  const std::string h5 = tmp("norm.h5");
  const auto W = values(4, 20), b = values(1, 21);
  {
    H5Writer w(h5);
    w.config(R"({"class_name": "Sequential", "config": {"name": "s", "layers": [
      {"class_name": "Dense", "config": {"name": "d", "units": 1, "batch_input_shape": [null, 4]}}]}})",
             true);
    w.layer("d", {"d/kernel:0", "d/bias:0"});
    w.array("d", "d/kernel:0", {4, 1}, W);
    w.array("d", "d/bias:0", {1}, b);
  }
  const std::string norm = tmp("norm.json");
  std::ofstream(norm) << R"({"in_offset": [1, 2, 3, 4], "in_scale": [0.5, 0.5, 2, 2], "out_offset": [10], "out_scale": [3]})";
  const std::string out = tmp("norm.nlsm");
  ASSERT_EQ(run_cli("model import " + h5 + " --out " + out + " --rig msd --norm " + norm).code, 0);
  const auto x = input(4, 1);
  std::vector<double> xn = {(x[0] - 1) * 0.5, (x[1] - 2) * 0.5, (x[2] - 3) * 2, (x[3] - 4) * 2};
  expect_close(run_model(out, x), {affine(xn, W, &b, 1)[0] * 3 + 10});

  std::ofstream(norm) << R"({"in_offset": [1, 2, 3], "in_scale": [1, 1, 1, 1], "out_offset": [0], "out_scale": [1]})";
  const auto bad = run_cli("model import " + h5 + " --out " + tmp("norm2.nlsm") + " --rig msd --norm " + norm);
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("in_offset"), std::string::npos) << bad.output;
  EXPECT_FALSE(nlsoft::test::file_exists(tmp("norm2.nlsm")));
}

void expect_refused(const std::string& config, const std::string& layer_name, const std::string& h5name) {
  const std::string h5 = tmp(h5name);
  {
    H5Writer w(h5);
    w.config(config, true);
  }
  try {
    read_keras_h5(h5);
    ADD_FAILURE() << "accepted " << config;
  } catch (const PipelineError& e) {
    EXPECT_NE(std::string(e.what()).find(layer_name), std::string::npos) << e.what();
  }
  const auto r = run_cli("model import " + h5 + " --out " + tmp(h5name + ".nlsm") + " --rig msd");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find(layer_name), std::string::npos) << r.output;
  EXPECT_FALSE(nlsoft::test::file_exists(tmp(h5name + ".nlsm")));
}

TEST(KerasImport, RefusesWhatItCannotRun) {
  expect_refused(R"({"class_name": "Sequential", "config": {"name": "s", "layers": [
      {"class_name": "InputLayer", "config": {"batch_input_shape": [null, 1, 4], "name": "in"}},
      {"class_name": "Conv1D", "config": {"name": "conv1d_7", "filters": 2, "kernel_size": [1]}}]}})",
                 "conv1d_7", "conv.h5");
  expect_refused(R"({"class_name": "Sequential", "config": {"name": "s", "layers": [
      {"class_name": "Dense", "config": {"name": "soft_out", "units": 2, "activation": "softmax",
       "batch_input_shape": [null, 4]}}]}})",
                 "soft_out", "softmax.h5");
  expect_refused(R"({"class_name": "Sequential", "config": {"name": "s", "layers": [
      {"class_name": "LSTM", "config": {"name": "lstm_2", "units": 2, "batch_input_shape": [null, 1, 4]}}]}})",
                 "lstm_2", "lstm.h5");
  expect_refused(R"({"class_name": "Functional", "config": {"name": "s", "layers": []}})", "Sequential",
                 "functional.h5");
}

TEST(KerasImport, RefusesNonHdf5AndMissingWeights) {
  const std::string junk = tmp("junk.h5");
  std::ofstream(junk) << "not hdf5";
  EXPECT_THROW(read_keras_h5(junk), PipelineError);
  EXPECT_THROW(read_keras_h5(tmp("does_not_exist.h5")), PipelineError);
  const std::string h5 = tmp("noweights.h5");
  {
    H5Writer w(h5);
    w.config(R"({"class_name": "Sequential", "config": {"name": "s", "layers": [
      {"class_name": "Dense", "config": {"name": "lonely", "units": 1, "batch_input_shape": [null, 4]}}]}})",
             true);
  }
  try {
    read_keras_h5(h5);
    ADD_FAILURE();
  } catch (const PipelineError& e) {
    EXPECT_NE(std::string(e.what()).find("lonely"), std::string::npos) << e.what();
  }
}

}  // namespace
