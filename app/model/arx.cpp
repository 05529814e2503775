#include "app/model/arx.hpp"

#include <cmath>

#include <Eigen/QR>
#include <nlohmann/json.hpp>

#include "app/model/error.hpp"

namespace nlsoft::model {

void ArxModel::predict(const double* x, double* y) const {
  const int p = layout.p();
  for (int j = 0; j < layout.n; ++j) {
    double s = theta(p, j);
    for (int i = 0; i < p; ++i) s += x[i] * theta(i, j);
    y[j] = s;
  }
}

ArxModel fit_arx(const Dataset& d, const std::vector<RowRange>& pieces) {
  const InputLayout& L = d.layout;
  long rows = 0;
  for (const RowRange& r : pieces) rows += std::max(0L, r.end - r.begin);
  if (rows < L.p() + 1)
    throw PipelineError("too few rows (" + std::to_string(rows) + ") to fit the ARX baseline's " +
                        std::to_string(L.p() + 1) + " coefficients per output");
  Eigen::MatrixXd A(rows, L.p() + 1), B(rows, L.n);
  long at = 0;
  for (const RowRange& r : pieces) {
    const long len = r.end - r.begin;
    if (len <= 0) continue;
    A.block(at, 0, len, L.p()) = d.X.middleRows(r.begin, len);
    B.middleRows(at, len) = d.Y.middleRows(r.begin, len);
    at += len;
  }
  A.col(L.p()).setOnes();
  ArxModel a;
  a.layout = L;
  a.theta = A.colPivHouseholderQr().solve(B);
  if (!a.theta.allFinite()) throw PipelineError("the ARX baseline's least squares gave no finite solution");
  return a;
}

std::string arx_to_json(const ArxModel& a) {
  nlohmann::json j;
  const InputLayout& L = a.layout;
  j["m"] = L.m;
  j["n"] = L.n;
  j["w"] = L.w;
  j["nd"] = L.nd;
  j["dd"] = L.dd;
  // Per output, its p + 1 coefficients in input-vector order, the bias last.
  j["theta"] = nlohmann::json::array();
  for (int c = 0; c < L.n; ++c) {
    std::vector<double> col(size_t(L.p() + 1));
    for (int i = 0; i <= L.p(); ++i) col[size_t(i)] = a.theta(i, c);
    j["theta"].push_back(col);
  }
  return j.dump();
}

ArxModel arx_from_json(const std::string& text, const std::string& where) {
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    ArxModel a;
    a.layout = InputLayout{j.at("m").get<int>(), j.at("n").get<int>(), j.at("w").get<int>(), j.at("nd").get<int>(),
                           j.at("dd").get<int>()};
    const InputLayout& L = a.layout;
    const auto& th = j.at("theta");
    if (L.m < 0 || L.n < 1 || L.w < 0 || L.nd < 1 || L.dd < 1 || th.size() != size_t(L.n))
      throw PipelineError(where + ": its ARX baseline has inconsistent dimensions");
    a.theta.resize(L.p() + 1, L.n);
    for (int c = 0; c < L.n; ++c) {
      const auto& col = th.at(size_t(c));
      if (col.size() != size_t(L.p() + 1)) throw PipelineError(where + ": its ARX baseline has a wrong column size");
      for (int i = 0; i <= L.p(); ++i) a.theta(i, c) = col.at(size_t(i)).get<double>();
    }
    return a;
  } catch (const nlohmann::json::exception& e) {
    throw PipelineError(where + ": its ARX baseline is not readable: " + e.what());
  }
}

}  // namespace nlsoft::model
