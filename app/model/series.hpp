#pragma once
// A logged run of a plant: per sample k the time, the input u(k) applied
// during [k, k+1), the output y(k) and the sensor signals l(k) read at k.
// CSV form: header "time,u0..u{m-1},y0..y{n-1},l0..l{w-1}", one row per k.
// A recorded run may have gaps (lost telemetry, a link outage): `breaks`
// lists the rows that do not follow the row before them by one control
// period, so no history window is built across one.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace nlsoft::model {

struct Series {
  int m = 0, n = 0, w = 0;
  Eigen::VectorXd time;  // s
  Eigen::MatrixXd u;     // rows x m
  Eigen::MatrixXd y;     // rows x n
  Eigen::MatrixXd l;     // rows x w
  std::vector<long> breaks;  // ascending rows r > 0 with a gap between r - 1 and r
  std::string name;          // where it came from ("run 12", a file), for messages
  long rows() const { return static_cast<long>(time.size()); }
  void resize(long rows, int m_, int n_, int w_);
};

// Throws PipelineError on a missing/misnamed column, a bad cell, or time
// that does not increase.
Series read_series_csv(const std::string& path);
Series parse_series_csv(std::istream& in, const std::string& name);
void write_series_csv(const std::string& path, const Series& s);  // atomic
void write_series_csv(std::ostream& out, const Series& s);

}  // namespace nlsoft::model
