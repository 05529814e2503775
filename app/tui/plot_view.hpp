#pragma once
// The live plots: a chosen signal against time (y_ref/y_hat/y_true per
// output axis, u per actuator, the solver's cost J, Newton iterations or
// compute time per step), with a time axis and a readout of the values at
// the right edge; and a 2-D path view of two chosen axes. Both scale to what
// is on screen.
#include <cstdint>
#include <string>
#include <vector>

#include "app/record/run_store.hpp"
#include "app/record/sample.hpp"
#include "app/tui/screen.hpp"

namespace nlsoft::console::tui {

// Ident: an identification run's u, measured y and sensors l, a strip each.
enum class PlotSignal { Y, U, Cost, Iter, Compute, Ident };

// "y", "u", "cost", "iter", "compute", "ident".
const char* plot_signal_name(PlotSignal s);
// false for anything else.
bool plot_signal_from_name(const std::string& name, PlotSignal* out);
PlotSignal next_plot_signal(PlotSignal s);
// "y, u, cost, iter or compute", for messages.
std::string plot_signal_names();

// Columns left of a time plot for its value labels.
inline constexpr int kTimePlotLabelWidth = 9;

struct TimeView {
  PlotSignal signal = PlotSignal::Y;
  double window_steps = 1300;  // control steps across the plot
  double rate_hz = 130;        // control steps per second, for the time axis
  // The step at the right edge: a paused or scrolled view shows what came
  // before it. Negative: the newest sample (live).
  int64_t end_step = -1;
  // A time cursor (paused views): the readout reads the sample at or before
  // it, and a vertical line marks it. Negative: none, the right edge reads.
  int64_t cursor_step = -1;
  // A recorded run drawn under the live one (`:overlay ID`), step for step:
  // both count steps from their RUN_START. Its y_true (or y_hat) on the y
  // strips, its u on the u strips.
  const RunSeries* overlay = nullptr;
  int64_t overlay_id = 0;
};

// One strip per axis (or actuator; the scalar signals get one), stacked in
// the box (y, x, h, w), the bottom row the time axis in seconds of control
// steps. Each strip's title line reads out the values at the cursor (or
// the right edge), and for y the tracking error.
void draw_time_plots(const Screen& screen, int y, int x, int h, int w, const std::vector<Sample>& samples,
                     const TimeView& view);

// Path of axes (ax, ay): y_ref, y_hat and y_true traces, equal scaling.
void draw_path_view(const Screen& screen, int y, int x, int h, int w, const std::vector<Sample>& samples, int ax,
                    int ay);

// Tick marks for a time axis from t0 to t1 seconds: a 1-2-5 spacing giving
// at most max_ticks marks.
std::vector<double> time_ticks(double t0, double t1, int max_ticks);

// The cursor moved by `columns` plot columns of a view ending at end_step
// and window_steps wide, kept inside the view (and after step 0, the run's
// start); a cursor outside it (none yet, or the view scrolled away) starts
// in the middle of what the view shows.
int64_t move_time_cursor(int64_t cursor, int64_t end_step, double window_steps, int plot_columns, int columns);

}  // namespace nlsoft::console::tui
