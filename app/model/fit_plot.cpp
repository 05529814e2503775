#include "app/model/fit_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/gnuplot_text.hpp"

namespace nlsoft::model {
namespace {

std::string num(double v) {
  char buf[32];
  if (!std::isfinite(v)) return "NaN";
  std::snprintf(buf, sizeof buf, "%.7g", v);
  return buf;
}

std::string fit_words(const Score& s) { return std::isfinite(s.fit) ? num(std::round(s.fit * 10) / 10) + " %" : "-"; }

}  // namespace

Eigen::VectorXd label_times(const Series& s, int nd, int dd, double period) {
  // The stretches between breaks exactly as build_dataset cuts them: a
  // stretch of hist samples or fewer gives no row.
  const long hist = std::max(nd, dd), q = s.rows();
  std::vector<double> t;
  long start = 0;
  std::vector<long> cuts;
  for (long b : s.breaks)
    if (b > start && b < q) cuts.push_back(b), start = b;
  cuts.push_back(q);
  start = 0;
  for (long end : cuts) {
    for (long k = start + hist - 1; k + 1 < end; ++k) t.push_back(period > 0 ? double(k + 1) * period : s.time(k + 1));
    start = end;
  }
  return Eigen::Map<Eigen::VectorXd>(t.data(), long(t.size()));
}

std::string fit_plot_script(const std::vector<FittedRun>& runs, const std::string& model_name, const std::string& unit,
                            FitImage format, long max_points) {
  int panels = 0;
  for (const FittedRun& r : runs) panels += int(r.y.cols());
  const int width = 1100, height = 260 * std::max(1, panels) + 60;
  std::string s = "# nlsoft-console model fit\n";
  s += format == FitImage::Svg
           ? "set terminal svg size " + std::to_string(width) + "," + std::to_string(height) +
                 " noenhanced font \"sans,10\" background \"white\"\n"
           : "set terminal pngcairo size " + std::to_string(width) + "," + std::to_string(height) +
                 " noenhanced font \"sans,9\" background \"white\"\n";
  s += "set encoding utf8\nset grid\nset key outside right top\nset datafile missing NaN\n";
  for (size_t k = 0; k < runs.size(); ++k) {
    const FittedRun& r = runs[k];
    const long rows = long(r.y.rows());
    const long stride = std::max(1L, (rows + max_points - 1) / std::max(1L, max_points));
    s += "$run" + std::to_string(k) + " << EOD\n";
    for (long i = 0; i < rows; i += stride) {
      std::string line = num(r.time(i));
      for (Eigen::Index j = 0; j < r.y.cols(); ++j) {
        line += " " + num(r.y(i, j)) + " " + num(r.net(i, j));
        line += " " + (r.arx.size() ? num(r.arx(i, j)) : std::string("NaN"));
      }
      s += line + "\n";
    }
    s += "EOD\n";
  }
  s += "set multiplot layout " + std::to_string(std::max(1, panels)) + ",1 title " +
       console::gnuplot_string("model fit: " + model_name + ", measured against free-run simulation") + "\n";
  for (size_t k = 0; k < runs.size(); ++k) {
    const FittedRun& r = runs[k];
    for (Eigen::Index j = 0; j < r.y.cols(); ++j) {
      const OutputFit& o = r.section.outputs[size_t(j)];
      std::string title = r.name + ", output " + o.name + ": free-run fit network " + fit_words(o.free_run);
      if (r.arx.size()) title += ", ARX " + fit_words(o.arx_free_run);
      const std::string data = "$run" + std::to_string(k), c = std::to_string(2 + 3 * j);
      s += "set title " + console::gnuplot_string(title) + "\nset xlabel \"t (s)\"\nset ylabel " + console::gnuplot_string(unit.empty() ? o.name : o.name + " (" + unit + ")") + "\n";
      s += "plot " + data + " using 1:" + c + " with lines lw 1.4 lc rgb \"#000000\" title \"measured\", \\\n";
      s += "     " + data + " using 1:" + std::to_string(3 + 3 * j) +
           " with lines lw 1.2 lc rgb \"#1f77b4\" title \"network (free run)\"";
      if (r.arx.size())
        s += ", \\\n     " + data + " using 1:" + std::to_string(4 + 3 * j) +
             " with lines lw 1.2 dt 2 lc rgb \"#ff7f0e\" title \"ARX (free run)\"";
      s += "\n";
    }
  }
  return s + "unset multiplot\n";
}

}  // namespace nlsoft::model
