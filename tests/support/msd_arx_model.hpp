#pragma once
// Test support: an msd model identified from the simulated plant by least
// squares (y(k+1) = a1 y(k) + a2 y(k-1) + b1 u(k) + b2 u(k-1)), written as a
// model file: a model good enough to control with, built in milliseconds and
// independent of the trainer.
#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "shared/model_file.hpp"
#include "shared/plant_msd.hpp"

namespace nlsoft::test {

inline std::vector<uint8_t> msd_arx_model_file() {
  MsdPlant p;
  p.reset(1);
  const float dt = 1e-3f;
  const int K = 20000;
  std::vector<double> u(K), y(K + 1);
  float yy;
  p.output(&yy);
  y[0] = yy;
  for (int k = 0; k < K; ++k) {
    const double t = k * 1e-3;
    u[k] = 1000 * std::sin(3 * t) * std::cos(7 * t) + 300 * std::sin(13 * t);
    const float uf = float(u[k]);
    p.step(&uf, dt);
    p.output(&yy);
    y[k + 1] = yy;
  }
  Eigen::MatrixXd A(K - 2, 4);
  Eigen::VectorXd b(K - 2);
  for (int k = 1; k < K - 1; ++k) {
    A.row(k - 1) << u[k], u[k - 1], y[k], y[k - 1];
    b(k - 1) = y[k + 1];
  }
  const Eigen::VectorXd w = A.colPivHouseholderQr().solve(b);
  Model<HostCapacity> M;
  M.m = M.n = 1;
  M.w = 0;
  M.nd = M.dd = 2;
  M.residual = true;  // y(k+1) = y(k) + net(x)
  M.layer_count = 1;
  M.layer[0] = Layer{LayerKind::Dense, Activation::Linear, Activation::Sigmoid, false, 4, 1, 0};
  static float P[15];
  for (int i = 0; i < 4; ++i) P[i] = 0.0f, P[4 + i] = 1.0f;
  P[8] = 0.0f, P[9] = 1.0f;
  P[10] = float(w(0)), P[11] = float(w(1)), P[12] = float(w(2) - 1.0), P[13] = float(w(3)), P[14] = 0.0f;
  M.params = P;
  M.param_count = 15;
  std::vector<uint8_t> file(model_file_size(1, 15));
  if (finalize_model(M) != Status::Ok || write_model(M, 0, file.data(), file.size()) != file.size()) file.clear();
  return file;
}

}  // namespace nlsoft::test
