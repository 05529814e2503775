#pragma once
// The live plots: y_ref, y_hat and y_true per output axis against time, and
// a 2-D path view of two chosen axes. Both scale to what is on screen.
#include <vector>

#include "app/record/sample.hpp"
#include "app/tui/screen.hpp"

namespace nlsoft::console::tui {

// One strip per axis, stacked in the box (y, x, h, w); the time window is the
// last `window_steps` control steps of `samples`.
void draw_time_plots(const Screen& screen, int y, int x, int h, int w, const std::vector<Sample>& samples,
                     double window_steps);

// Path of axes (ax, ay): y_ref, y_hat and y_true traces, equal scaling.
void draw_path_view(const Screen& screen, int y, int x, int h, int w, const std::vector<Sample>& samples, int ax,
                    int ay);

}  // namespace nlsoft::console::tui
