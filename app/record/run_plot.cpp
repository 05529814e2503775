#include "app/record/run_plot.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "host/files/cli_error.hpp"
#include "app/gnuplot_text.hpp"
#include "app/record/task_space.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

// A simulation (`simulate --svg`) has no id: its label names it.
std::string run_name(const PlottedRun& r) {
  if (r.row.id == 0) return r.row.label;
  return r.row.label.empty() ? fmt::format("run {}", r.row.id) : fmt::format("run {} ({})", r.row.id, r.row.label);
}

// Lines of at most `width` characters, broken at blanks where there are
// some (a reference's JSON has none, and is cut where it must be).
std::vector<std::string> wrap(const std::string& text, size_t width, const std::string& indent) {
  std::vector<std::string> out;
  std::string rest = text;
  while (rest.size() > width) {
    // Between items (two blanks) first, so "Lambda=1 1 1" stays whole.
    size_t cut = rest.rfind("  ", width);
    if (cut == std::string::npos || cut < width / 2) cut = rest.rfind(' ', width);
    if (cut == std::string::npos || cut < width / 2) cut = width;
    out.push_back(rest.substr(0, cut));
    const size_t next = rest.find_first_not_of(' ', cut);
    rest = indent + (next == std::string::npos ? "" : rest.substr(next));
  }
  out.push_back(rest);
  return out;
}

// The run's identity, tracking figure, reference and parameters at start;
// an identification run's identity and excitation (no controller ran, so
// neither a tracking figure nor the controller's parameters belong).
std::vector<std::string> caption_lines(const PlottedRun& r) {
  constexpr size_t kWidth = 140;
  std::vector<std::string> lines;
  if (r.row.kind == "ident") {
    // Its time as the picture's axis counts it: steps at the set rate (a
    // --sim-fast simulator's clock stands still).
    const RunSeries& s = r.series;
    const double rate = r.row.loop_rate_hz > 0 ? r.row.loop_rate_hz : 1.0;
    const double seconds = s.rows() ? double(s.step.back() - s.step.front() + 1) / rate : 0.0;
    lines.push_back(fmt::format("{}: identification on {} {}, {} samples, {:.2f} s at {:g} Hz", run_name(r),
                                r.row.platform, r.row.firmware, r.metrics.samples, seconds, rate));
    if (!r.row.excitation.empty())
      for (const std::string& l : wrap("  excitation " + r.row.excitation, kWidth, "    ")) lines.push_back(l);
    return lines;
  }
  const TrackingMetrics& t = r.metrics.has_true ? r.metrics.truth : r.metrics.predicted;
  lines.push_back(fmt::format("{}: {} {}, {} samples over {:.2f} s, nrmse {} ({})", run_name(r), r.row.platform,
                              r.row.firmware, r.metrics.samples, r.metrics.duration_s, nrmse_words(t.nrmse, true),
                              r.metrics.has_true ? "y_true" : "y_hat"));
  if (!r.row.reference.empty())
    for (const std::string& l : wrap("  reference " + r.row.reference, kWidth, "    ")) lines.push_back(l);
  std::string params;
  for (const ParamRecord& p : r.params)
    if (p.at_start) params += (params.empty() ? "" : "  ") + p.name + "=" + p.value;
  if (!params.empty())
    for (const std::string& l : wrap("  " + params, kWidth, "  ")) lines.push_back(l);
  return lines;
}

// Columns of a run's data block: t, y_ref[n], y_hat[n], y_true[n], u[m],
// l[w] (the sensors of an identification run).
struct Columns {
  int n, m;
  int l(int j) const { return 2 + 3 * n + m + j; }
  int ref(int a) const { return 2 + a; }
  int hat(int a) const { return 2 + n + a; }
  int truth(int a) const { return 2 + 2 * n + a; }
  int u(int i) const { return 2 + 3 * n + i; }
};

std::string data_block(const PlottedRun& r, int index, size_t max_points) {
  const RunSeries& s = r.series;
  const size_t rows = s.rows();
  const size_t stride = std::max<size_t>(1, (rows + max_points - 1) / std::max<size_t>(1, max_points));
  const double rate = r.row.loop_rate_hz > 0 ? r.row.loop_rate_hz : 1.0;
  const uint32_t step0 = rows ? s.step[0] : 0;
  std::string out = fmt::format("$run{} << EOD\n", index);
  auto cell = [&](bool have, float v) { return have ? fmt::format(" {:.7g}", v) : std::string(" NaN"); };
  for (size_t i = 0; i < rows; i += stride) {
    out += fmt::format("{:.6f}", double(s.step[i] - step0) / rate);
    for (int a = 0; a < s.n; ++a) out += cell(s.has_y_ref, s.y_ref[i * size_t(s.n) + size_t(a)]);
    for (int a = 0; a < s.n; ++a) out += cell(s.has_y_hat, s.y_hat[i * size_t(s.n) + size_t(a)]);
    for (int a = 0; a < s.n; ++a) out += cell(s.has_y_true, s.y_true[i * size_t(s.n) + size_t(a)]);
    for (int a = 0; a < s.m; ++a) out += cell(s.has_u, s.u[i * size_t(s.m) + size_t(a)]);
    for (int a = 0; a < s.w; ++a) out += cell(s.has_l, s.l[i * size_t(s.w) + size_t(a)]);
    out += '\n';
  }
  return out + "EOD\n";
}

// One series of one run: the second run of an overlay is dashed and named.
std::string series(const std::vector<PlottedRun>& runs, size_t k, const std::string& using_, const std::string& title,
                   const std::string& colour) {
  const std::string name = runs.size() > 1 ? fmt::format("run {} {}", runs[k].row.id, title) : title;
  return fmt::format("$run{} using {} with lines lw 1.2 dt {} lc rgb {} title {}", k, using_, k == 0 ? 1 : 2,
                     gnuplot_string(colour), gnuplot_string(name));
}

}  // namespace

PlottedRun load_plotted_run(RunStore& store, int64_t id) {
  PlottedRun r;
  r.row = store.run(id);
  r.series = store.series(id);
  if (r.series.rows() == 0) throw CliError(fmt::format("run {} has no samples to plot", id));
  r.metrics = run_metrics(store, id);
  r.params = store.params(id);
  const RigColumns c = rig_columns(r.row.platform, r.series.n, r.series.m, r.series.w);
  for (int a = 0; a < r.series.n; ++a)
    r.output_labels.push_back(axis_label(c.output_names, c.output_units, size_t(a), fmt::format("y{}", a)));
  for (int i = 0; i < r.series.m; ++i)
    r.input_labels.push_back(axis_label(c.input_names, c.input_units, size_t(i), fmt::format("u{}", i)));
  for (int j = 0; j < r.series.w; ++j)
    r.sensor_labels.push_back(axis_label(c.sensor_names, c.sensor_units, size_t(j), fmt::format("l{}", j)));
  return r;
}

namespace {

const char* const kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b",
                                "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

std::string label(const std::vector<std::string>& labels, int i, const char* prefix) {
  return size_t(i) < labels.size() && !labels[size_t(i)].empty() ? labels[size_t(i)] : fmt::format("{}{}", prefix, i);
}

// A series in a legend: its column's name (u0, as the CSV and `runs show`
// say it) and the rig's ("u0 h1").
std::string legend(const std::vector<std::string>& labels, int i, const char* prefix) {
  const std::string column = fmt::format("{}{}", prefix, i);
  return size_t(i) < labels.size() && !labels[size_t(i)].empty() && labels[size_t(i)] != column
             ? column + " " + labels[size_t(i)]
             : column;
}

// One unit for a panel of several series when they share it ("u (kV)").
std::string shared_unit(const std::vector<std::string>& labels, const char* fallback) {
  std::string unit;
  for (const std::string& l : labels) {
    const size_t open = l.rfind(" (");
    const std::string u = open == std::string::npos ? "" : l.substr(open);
    if (u.empty() || (!unit.empty() && u != unit)) return std::string(fallback);
    unit = u;
  }
  return unit.empty() ? std::string(fallback) : fallback + unit;
}

// "plot a, \ b, ..." continued over lines; a panel with nothing to draw plots NaN.
std::string plot_parts(std::vector<std::string> parts) {
  if (parts.empty()) parts.push_back("NaN notitle");
  std::string s;
  for (size_t i = 0; i < parts.size(); ++i) s += (i ? ", \\\n     " : "") + parts[i];
  return s;
}

// Output a: each run's reference, prediction and measurement against time.
std::string output_panel(const std::vector<PlottedRun>& runs, const Columns& c, int a) {
  const std::string name = label(runs[0].output_labels, a, "y");
  std::string s = fmt::format(
      "set title {}\nset xlabel \"t (s)\"\nset ylabel {}\n",
      gnuplot_string(name == fmt::format("y{}", a) ? "output " + name : fmt::format("output y{}: {}", a, name)),
      gnuplot_string(name));
  std::vector<std::string> parts;
  for (size_t k = 0; k < runs.size(); ++k) {
    const RunSeries& rs = runs[k].series;
    if (rs.has_y_ref) parts.push_back(series(runs, k, fmt::format("1:{}", c.ref(a)), "y_ref", "#000000"));
    if (rs.has_y_hat) parts.push_back(series(runs, k, fmt::format("1:{}", c.hat(a)), "y_hat", "#1f77b4"));
    if (rs.has_y_true) parts.push_back(series(runs, k, fmt::format("1:{}", c.truth(a)), "y_true", "#d62728"));
  }
  return s + "plot " + plot_parts(parts) + "\n";
}

// The m inputs of every run that sent them, in one panel.
std::string inputs_panel(const std::vector<PlottedRun>& runs, const Columns& c, int m) {
  std::vector<std::string> parts;
  for (size_t k = 0; k < runs.size(); ++k) {
    if (!runs[k].series.has_u) continue;
    for (int i = 0; i < m; ++i)
      parts.push_back(
          series(runs, k, fmt::format("1:{}", c.u(i)), legend(runs[0].input_labels, i, "u"), kColours[size_t(i) % 10]));
  }
  return fmt::format("set title \"actuator inputs u\"\nset xlabel \"t (s)\"\nset ylabel {}\nplot ",
                     gnuplot_string(shared_unit(runs[0].input_labels, "u"))) +
         plot_parts(parts) + "\n";
}

// The w sensors of every run with as many, in one panel.
std::string sensors_panel(const std::vector<PlottedRun>& runs, const Columns& c, int w) {
  std::vector<std::string> parts;
  for (size_t k = 0; k < runs.size(); ++k) {
    if (!runs[k].series.has_l || runs[k].series.w != w) continue;
    for (int j = 0; j < w; ++j)
      parts.push_back(series(runs, k, fmt::format("1:{}", c.l(j)), legend(runs[0].sensor_labels, j, "l"),
                             kColours[size_t(j) % 10]));
  }
  return fmt::format("set title \"sensors l\"\nset xlabel \"t (s)\"\nset ylabel {}\nplot ",
                     gnuplot_string(shared_unit(runs[0].sensor_labels, "l"))) +
         plot_parts(parts) + "\n";
}

// y1 against y0, to scale.
std::string path_panel(const std::vector<PlottedRun>& runs, const Columns& c) {
  const PlottedRun& r0 = runs[0];
  std::string s = fmt::format("set title {}\nset xlabel {}\nset ylabel {}\nset size ratio -1\nplot ",
                              gnuplot_string(fmt::format("x-y path (y0 across, y1 up)")),
                              gnuplot_string(label(r0.output_labels, 0, "y")),
                              gnuplot_string(label(r0.output_labels, 1, "y")));
  std::vector<std::string> parts;
  for (size_t k = 0; k < runs.size(); ++k) {
    const RunSeries& rs = runs[k].series;
    if (rs.has_y_ref) parts.push_back(series(runs, k, fmt::format("{}:{}", c.ref(0), c.ref(1)), "y_ref path", "#000000"));
    if (rs.has_y_hat) parts.push_back(series(runs, k, fmt::format("{}:{}", c.hat(0), c.hat(1)), "y_hat path", "#1f77b4"));
    if (rs.has_y_true)
      parts.push_back(series(runs, k, fmt::format("{}:{}", c.truth(0), c.truth(1)), "y_true path", "#d62728"));
  }
  return s + plot_parts(parts) + "\nset size noratio\n";
}

}  // namespace

std::string run_plot_script(const std::vector<PlottedRun>& runs, ImageFormat format, size_t max_points) {
  if (runs.empty()) throw CliError("runs plot: no run given");
  const int n = runs[0].series.n;
  const int m = runs[0].series.m;
  for (const PlottedRun& r : runs)
    if (r.series.n != n || r.series.m != m)
      throw CliError(fmt::format("runs plot: run {} has n={} m={}, run {} has n={} m={}: overlays need one rig",
                                 runs[0].row.id, n, m, r.row.id, r.series.n, r.series.m));
  const bool path = n >= 2;
  // The sensors of an identification run (the first run's; an overlay of
  // two keeps both when they have as many).
  const int w = runs[0].series.has_l ? runs[0].series.w : 0;
  const int panels = n + (m > 0 ? 1 : 0) + (w > 0 ? 1 : 0) + (path ? 1 : 0);
  std::vector<std::string> caption;
  for (const PlottedRun& r : runs)
    for (const std::string& l : caption_lines(r)) caption.push_back(l);
  const int width = 1100, height = 260 * panels + 18 * int(caption.size()) + 40;

  std::string s = "# nlsoft-console runs plot\n";
  // noenhanced: names like y_ref are text, not subscripts.
  s += format == ImageFormat::Svg
           ? fmt::format("set terminal svg size {},{} noenhanced font \"sans,10\" background \"white\"\n", width, height)
           : fmt::format("set terminal pngcairo size {},{} noenhanced font \"sans,9\" background \"white\"\n", width,
                         height);
  s += "set encoding utf8\nset grid\nset key outside right top\nset datafile missing NaN\n";
  for (size_t k = 0; k < runs.size(); ++k) s += data_block(runs[k], int(k), max_points);
  std::string title;
  for (const std::string& l : caption) title += (title.empty() ? "" : "\n") + l;
  s += fmt::format("set multiplot layout {},1 title {} font \"monospace,8\"\n", panels, gnuplot_string(title));
  const Columns c{n, m};
  for (int a = 0; a < n; ++a) s += output_panel(runs, c, a);
  if (m > 0) s += inputs_panel(runs, c, m);
  if (w > 0) s += sensors_panel(runs, c, w);
  if (path) s += path_panel(runs, c);
  s += "unset multiplot\n";
  return s;
}

std::string simulation_plot_script(const SimulationPicture& p, size_t max_points) {
  const Trace& t = *p.trace;
  PlottedRun r;
  r.row.label = fmt::format("simulate {} on {}", p.reference, p.rig);
  r.row.platform = p.rig;
  r.row.firmware = "(simulated on this host)";
  r.row.loop_rate_hz = t.dt > 0 ? 1.0 / double(t.dt) : 1.0;
  r.row.n = t.n;
  r.row.m = t.m;
  // Every row a control step; y_ref, y_hat, y_true and u in each.
  RunSeries& s = r.series;
  s.n = t.n;
  s.m = t.m;
  for (long k = 0; k < t.rows(); ++k) s.step.push_back(uint32_t(k + 1));
  s.y_ref = t.y_ref, s.y_hat = t.y_hat, s.y_true = t.y_true, s.u = t.u;
  s.has_y_ref = s.has_y_hat = s.has_y_true = s.has_u = true;
  r.metrics.samples = uint64_t(t.rows());
  r.metrics.duration_s = double(t.rows()) * double(t.dt);
  r.metrics.has_true = true;
  r.metrics.truth = p.truth;
  r.metrics.predicted = p.predicted;
  r.output_labels = p.output_labels;
  r.input_labels = p.input_labels;
  return run_plot_script({r}, p.svg ? ImageFormat::Svg : ImageFormat::Png, max_points);
}

}  // namespace nlsoft::console
