#pragma once
// `model fit --svg/--png`: per run and output, the measured output against
// the network's free-run simulation (and the ARX baseline's) over time.
// This file writes the gnuplot script only; the console draws it
// (app/record/gnuplot.hpp), so what is drawn is testable without gnuplot.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "app/model/model_fit.hpp"
#include "app/model/series.hpp"

namespace nlsoft::model {

struct FittedRun {
  std::string name;                // "run 3", a file
  Eigen::VectorXd time;            // s, of each row's label y(k+1)
  Eigen::MatrixXd y, net, arx;     // measured, network free run, ARX free run (empty: none)
  FitSection section;
};

// The label times of build_dataset(s, nd, dd)'s rows, in row order: the
// series' own, or with period > 0 its sample index times the control
// period (a run's firmware clock is not the rig's time under --sim-fast).
Eigen::VectorXd label_times(const Series& s, int nd, int dd, double period = 0);

enum class FitImage { Svg, Png };

// unit: the outputs' ("" none), on the y axes.
std::string fit_plot_script(const std::vector<FittedRun>& runs, const std::string& model_name, const std::string& unit,
                            FitImage format, long max_points = 4000);

}  // namespace nlsoft::model
