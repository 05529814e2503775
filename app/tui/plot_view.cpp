#include "app/tui/plot_view.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "app/tui/canvas.hpp"
#include "app/tui/curses.hpp"
#include "app/tui/fit_text.hpp"

namespace nlsoft::console::tui {

namespace tf = protocol::telemetry_field;

namespace {

constexpr int kLabelWidth = kTimePlotLabelWidth;
constexpr int kMaxTraces = 16;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One line in a strip. Without colour the glyph is what tells traces apart,
// so every trace of a strip gets its own.
struct Trace {
  std::string name;
  char glyph;
  int attr;
  std::function<double(const Sample&)> value;  // NaN when the sample lacks it
  // A recorded run's column instead (the overlay): row r's value is
  // column[r * stride + offset] at step[r].
  const RunSeries* series = nullptr;
  const std::vector<float>* column = nullptr;
  size_t stride = 1, offset = 0;
};

// The overlay's trace for y axis `a` or actuator `i`; none if the run
// lacks it.
void add_overlay(std::vector<Trace>& traces, const Screen& screen, const TimeView& view, bool y, int index) {
  const RunSeries* r = view.overlay;
  if (!r) return;
  Trace t{fmt::format("run {}", view.overlay_id), 'o', screen.series_attr(3), {}};
  t.series = r;
  if (y && (r->has_y_true || r->has_y_hat) && index < r->n) {
    t.column = r->has_y_true ? &r->y_true : &r->y_hat;
    t.stride = size_t(r->n);
  } else if (!y && r->has_u && index < r->m) {
    t.column = &r->u;
    t.stride = size_t(r->m);
  } else {
    return;
  }
  t.offset = size_t(index);
  traces.push_back(std::move(t));
}

// Calls f(step, value) for every finite point of the trace in [t0, t1].
template <class F>
void for_each_point(const Trace& t, const std::vector<Sample>& samples, double t0, double t1, F&& f) {
  if (t.series) {
    const RunSeries& r = *t.series;
    for (size_t i = 0; i < r.rows(); ++i) {
      if (r.step[i] < t0 || r.step[i] > t1) continue;
      const double v = double((*t.column)[i * t.stride + t.offset]);
      if (std::isfinite(v)) f(double(r.step[i]), v);
    }
    return;
  }
  for (const Sample& s : samples) {
    if (s.step < t0 || s.step > t1) continue;
    const double v = t.value(s);
    if (std::isfinite(v)) f(double(s.step), v);
  }
}

struct Strip {
  std::string title;
  std::vector<Trace> traces;
  int error_axis = -1;  // y strips: read out true (or hat) minus ref on this axis
};

double field_value(const Sample& s, uint8_t field, int i) {
  if (!s.has(field)) return kNaN;
  switch (field) {
    case tf::kYRef: return i < s.n ? double(s.y_ref()[i]) : kNaN;
    case tf::kYHat: return i < s.n ? double(s.y_hat()[i]) : kNaN;
    case tf::kYTrue: return i < s.n ? double(s.y_true()[i]) : kNaN;
    case tf::kU: return i < s.m ? double(s.u()[i]) : kNaN;
    default: return kNaN;
  }
}

Trace y_trace(const Screen& screen, uint8_t field, int axis) {
  const char* name = field == tf::kYRef ? "ref" : field == tf::kYHat ? "hat" : "true";
  const char glyph = field == tf::kYRef ? '.' : field == tf::kYHat ? '+' : '*';
  const Role role = field == tf::kYRef ? Role::Ref : field == tf::kYHat ? Role::Hat : Role::True;
  return {name, glyph, screen.attr(role), [field, axis](const Sample& s) { return field_value(s, field, axis); }};
}

char index_glyph(int i) { return i < 10 ? char('0' + i) : char('a' + (i - 10)); }

std::vector<Strip> strips_for(const Screen& screen, const TimeView& view, const Sample& last, int plot_rows) {
  const PlotSignal signal = view.signal;
  std::vector<Strip> out;
  switch (signal) {
    case PlotSignal::Y:
      for (int a = 0; a < last.n; ++a) {
        out.push_back({fmt::format("y{}", a),
                       {y_trace(screen, tf::kYRef, a), y_trace(screen, tf::kYHat, a), y_trace(screen, tf::kYTrue, a)},
                       a});
        add_overlay(out.back().traces, screen, view, true, a);
      }
      break;
    case PlotSignal::U:
      // A strip per actuator when they fit, else all in one with a glyph each.
      if (plot_rows >= 3 * last.m) {
        for (int i = 0; i < last.m; ++i) {
          out.push_back({"", {{fmt::format("u{}", i), index_glyph(i), screen.series_attr(i),
                               [i](const Sample& s) { return field_value(s, tf::kU, i); }}}});
          add_overlay(out.back().traces, screen, view, false, i);
        }
      } else {
        Strip st{"u", {}};
        for (int i = 0; i < last.m && i < kMaxTraces; ++i)
          st.traces.push_back({fmt::format("u{}", i), index_glyph(i), screen.series_attr(i),
                               [i](const Sample& s) { return field_value(s, tf::kU, i); }});
        out.push_back(st);
      }
      break;
    case PlotSignal::Ident: {
      // An identification run on 80x24: inputs, measured outputs and
      // sensors, each kind one strip with a glyph per channel, so the three
      // fit whatever m, n and w are.
      Strip su{"u", {}}, sy{"y", {}}, sl{"l", {}};
      for (int i = 0; i < last.m && i < kMaxTraces; ++i)
        su.traces.push_back({fmt::format("u{}", i), index_glyph(i), screen.series_attr(i),
                             [i](const Sample& s) { return field_value(s, tf::kU, i); }});
      for (int a = 0; a < last.n && a < kMaxTraces; ++a)
        sy.traces.push_back({fmt::format("y{}", a), index_glyph(a), screen.series_attr(a),
                             [a](const Sample& s) { return field_value(s, tf::kYTrue, a); }});
      for (int i = 0; i < last.w && i < kMaxTraces; ++i)
        sl.traces.push_back({fmt::format("l{}", i), index_glyph(i), screen.series_attr(i),
                             [i](const Sample& s) { return i < s.w ? double(s.l[i]) : kNaN; }});
      out.push_back(su);
      if (!sy.traces.empty()) out.push_back(sy);
      if (!sl.traces.empty()) out.push_back(sl);
      break;
    }
    case PlotSignal::Cost:
      out.push_back({"cost", {{"J", '*', screen.series_attr(0),
                               [](const Sample& s) { return s.has(tf::kCost) ? double(s.cost) : kNaN; }}}});
      break;
    case PlotSignal::Iter:
      out.push_back({"Newton", {{"iterations", '*', screen.series_attr(0),
                                 [](const Sample& s) { return s.has(tf::kSolver) ? double(s.iterations) : kNaN; }}}});
      break;
    case PlotSignal::Compute:
      out.push_back({"compute", {{"us/step", '*', screen.series_attr(0),
                                  [](const Sample& s) { return s.has(tf::kSolver) ? double(s.compute_us) : kNaN; }}}});
      break;
  }
  return out;
}

// Braille dots look alike whatever the series; only colour tells several
// apart, so without colour a strip of several traces draws glyphs instead.
bool use_braille(const Screen& screen, const Strip& st) {
  return screen.utf8() && (screen.colour() || st.traces.size() == 1);
}

std::string number(double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v) : "-"; }

// "y0  ━ ref 1.2  ━ hat 1.19  ━ true 1.18  err -0.02": every trace's mark,
// name and value at the right edge; the marks are the plot's own glyphs
// when those are what tells the traces apart.
void legend(const Screen& screen, int y, int x, int w, const Strip& st, const Sample* at) {
  int cx = x;
  if (!st.title.empty()) {
    put(y, cx, st.title, w, screen.attr(Role::KeyName));
    cx += int(st.title.size()) + 2;
  }
  // An item is drawn whole or not at all: a value cut short would read as
  // another number. The error, last, is the first to go.
  auto item_fits = [&](const std::string& item) { return cx + int(text_columns(item)) <= x + w; };
  const bool braille = use_braille(screen, st);
  for (const Trace& t : st.traces) {
    std::string item = fmt::format("{} {}", braille ? "\u2501" : std::string(1, t.glyph), t.name);
    if (at && !t.series) item += " " + number(t.value(*at));
    if (!item_fits(item)) return;
    put(y, cx, item, x + w - cx, t.attr);
    cx += int(text_columns(item)) + 2;
  }
  if (st.error_axis >= 0 && at) {
    const int a = st.error_axis;
    const bool have_true = at->has(tf::kYTrue);
    const double e = field_value(*at, have_true ? tf::kYTrue : tf::kYHat, a) - field_value(*at, tf::kYRef, a);
    const std::string item = fmt::format("err {}", number(e));
    if (item_fits(item)) put(y, cx, item, x + w - cx, screen.attr(Role::KeyName));
  }
}

// Range with a margin, never empty.
void pad_range(double& lo, double& hi) {
  if (!(lo <= hi)) lo = 0, hi = 1;
  const double span = hi - lo, mid = 0.5 * (lo + hi);
  const double half = span > 1e-12 ? 0.55 * span : std::max(1e-3, std::fabs(mid) * 0.05);
  lo = mid - half;
  hi = mid + half;
}

void draw_time_axis(const Screen& screen, int y, int x, int w, double t0, double t1) {
  fill_row(y, x, w, 0);
  if (w < 8 || !(t1 > t0)) return;
  const int max_ticks = std::max(2, w / 9);
  for (double t : time_ticks(t0, t1, max_ticks)) {
    const int cx = x + int(std::lround((t - t0) / (t1 - t0) * (w - 1)));
    const std::string label = fmt::format("{:g}s", std::fabs(t) < 1e-9 ? 0.0 : t);
    const int lx = std::min(std::max(x, cx - int(label.size()) / 2), x + w - int(label.size()));
    put(y, lx, label, int(label.size()), screen.attr(Role::Dim));
  }
}

}  // namespace

const char* plot_signal_name(PlotSignal s) {
  switch (s) {
    case PlotSignal::Y: return "y";
    case PlotSignal::U: return "u";
    case PlotSignal::Cost: return "cost";
    case PlotSignal::Iter: return "iter";
    case PlotSignal::Compute: return "compute";
    case PlotSignal::Ident: return "ident";
  }
  return "y";
}

bool plot_signal_from_name(const std::string& name, PlotSignal* out) {
  for (PlotSignal s :
       {PlotSignal::Y, PlotSignal::U, PlotSignal::Cost, PlotSignal::Iter, PlotSignal::Compute, PlotSignal::Ident})
    if (name == plot_signal_name(s)) {
      *out = s;
      return true;
    }
  return false;
}

PlotSignal next_plot_signal(PlotSignal s) {
  switch (s) {
    case PlotSignal::Y: return PlotSignal::U;
    case PlotSignal::U: return PlotSignal::Cost;
    case PlotSignal::Cost: return PlotSignal::Iter;
    case PlotSignal::Iter: return PlotSignal::Compute;
    case PlotSignal::Compute: return PlotSignal::Ident;
    case PlotSignal::Ident: return PlotSignal::Y;
  }
  return PlotSignal::Y;
}

std::string plot_signal_names() { return "y, u, cost, iter, compute or ident"; }

std::vector<double> time_ticks(double t0, double t1, int max_ticks) {
  std::vector<double> out;
  if (!(t1 > t0) || max_ticks < 1) return out;
  const double raw = (t1 - t0) / max_ticks;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double f : {1.0, 2.0, 5.0, 10.0})
    if (f * mag >= raw) {
      step = f * mag;
      break;
    }
  // Multiples of the step, not a running sum, so labels stay round.
  for (double i = std::ceil(t0 / step - 1e-9); i * step <= t1 + 1e-9 * step; ++i) out.push_back(i * step);
  return out;
}

void draw_time_plots(const Screen& screen, int y, int x, int h, int w, const std::vector<Sample>& samples,
                     const TimeView& view) {
  if (samples.empty()) {
    put(y + h / 2, x + 2, "no telemetry yet: start a run (F5) to see y_ref, y_hat and y_true", w - 4,
        screen.attr(Role::Dim));
    return;
  }
  // The newest sample at or before the cursor, or the view's right edge.
  const int64_t end = view.end_step < 0 ? int64_t(samples.back().step) : view.end_step;
  const double window = std::max(1.0, view.window_steps);
  const bool cursor = view.cursor_step >= 0 && view.cursor_step <= end && double(end - view.cursor_step) <= window;
  const int64_t read = cursor ? view.cursor_step : end;
  auto last_it = std::upper_bound(samples.begin(), samples.end(), read,
                                  [](int64_t e, const Sample& s) { return e < int64_t(s.step); });
  const Sample* at = last_it == samples.begin() ? nullptr : &*(last_it - 1);
  const Sample& shape = at ? *at : samples.back();
  const int plot_rows = h - 1;  // the last row is the time axis
  const std::vector<Strip> strips = strips_for(screen, view, shape, plot_rows);
  const int count = int(strips.size());
  if (count <= 0 || plot_rows < 3 * count) {
    put(y, x, "window too small for the plots", w, screen.attr(Role::Warn));
    return;
  }
  const double t1 = double(end), t0 = t1 - window;
  const int strip_h = plot_rows / count;
  const int pw = w - kLabelWidth;
  for (int si = 0; si < count; ++si) {
    const Strip& st = strips[size_t(si)];
    const int sy = y + si * strip_h;
    const int ph = strip_h - 1;
    if (ph < 2 || pw < 8) continue;
    double lo = INFINITY, hi = -INFINITY;
    for (const Trace& t : st.traces)
      for_each_point(t, samples, t0, t1, [&](double, double v) { lo = std::min(lo, v), hi = std::max(hi, v); });
    pad_range(lo, hi);
    legend(screen, sy, x, w, st, at);
    put(sy + 1, x, fmt::format("{:>8.4g}", hi), kLabelWidth - 1, screen.attr(Role::Dim));
    put(sy + ph, x, fmt::format("{:>8.4g}", lo), kLabelWidth - 1, screen.attr(Role::Dim));
    attrset(screen.attr(Role::Border));
    mvvline(sy + 1, x + kLabelWidth - 1, screen.utf8() ? ACS_VLINE : '|', ph);
    attrset(A_NORMAL);
    Canvas c(pw, ph, use_braille(screen, st));
    int attrs[kMaxTraces + 1] = {0};
    char glyphs[kMaxTraces + 1] = {' '};
    const size_t nt = std::min(st.traces.size(), size_t(kMaxTraces));
    for (size_t ti = 0; ti < nt; ++ti) {
      attrs[ti + 1] = st.traces[ti].attr;
      glyphs[ti + 1] = st.traces[ti].glyph;
    }
    for (size_t ti = 0; ti < nt; ++ti) {
      bool have = false;
      int px = 0, py = 0;
      for_each_point(st.traces[ti], samples, t0, t1, [&](double step, double v) {
        const int cx = int(std::lround((step - t0) / window * (c.width() - 1)));
        const int cy = int(std::lround((hi - v) / (hi - lo) * (c.height() - 1)));
        if (have) c.line(px, py, cx, cy, uint8_t(ti + 1));
        else c.dot(cx, cy, uint8_t(ti + 1));
        px = cx, py = cy, have = true;
      });
    }
    c.draw(sy + 1, x + kLabelWidth, attrs, glyphs);
    if (cursor) {
      const int cx = x + kLabelWidth + int(std::lround((double(read) - t0) / window * (pw - 1)));
      attrset(screen.attr(Role::KeyName));
      mvvline(sy + 1, cx, screen.utf8() ? ACS_VLINE : '|', ph);
      attrset(A_NORMAL);
    }
  }
  const double rate = view.rate_hz > 0 ? view.rate_hz : 1.0;
  draw_time_axis(screen, y + h - 1, x + kLabelWidth, pw, t0 / rate, t1 / rate);
}

int64_t move_time_cursor(int64_t cursor, int64_t end_step, double window_steps, int plot_columns, int columns) {
  const double window = std::max(1.0, window_steps);
  const double t0 = double(end_step) - window;
  const double per_column = window / std::max(1, plot_columns - 1);
  const double lo = std::max(0.0, t0), hi = double(end_step);
  if (cursor < 0 || double(cursor) > hi || double(cursor) < lo) return int64_t(std::llround(0.5 * (lo + hi)));
  // At least one step per key, so a cursor on a zoomed-in view still moves.
  const double by = columns * std::max(1.0, per_column);
  return int64_t(std::llround(std::min(hi, std::max(lo, double(cursor) + by))));
}

void draw_path_view(const Screen& screen, int y, int x, int h, int w, const std::vector<Sample>& samples, int ax,
                    int ay) {
  if (samples.empty()) {
    put(y + h / 2, x + 2, "no telemetry yet: start a run (F5) to see the path", w - 4, screen.attr(Role::Dim));
    return;
  }
  const int n = samples.back().n;
  if (n < 2) {
    put(y + h / 2, x + 2, "the path view needs two output axes (this rig has one)", w - 4, screen.attr(Role::Dim));
    return;
  }
  ax %= n;
  ay %= n;
  Strip st{fmt::format("path y{} \u2192 / y{} \u2191  (x: change axes)", ax, ay),
           {y_trace(screen, tf::kYRef, ax), y_trace(screen, tf::kYHat, ax), y_trace(screen, tf::kYTrue, ax)}};
  legend(screen, y, x, w, st, nullptr);
  const int ph = h - 1, pw = w;
  if (ph < 3 || pw < 6) return;
  const uint8_t fields[] = {tf::kYRef, tf::kYHat, tf::kYTrue};
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Sample& s : samples)
    for (uint8_t f : fields) {
      const double vx = field_value(s, f, ax), vy = field_value(s, f, ay);
      if (!std::isfinite(vx) || !std::isfinite(vy)) continue;
      x0 = std::min(x0, vx), x1 = std::max(x1, vx);
      y0 = std::min(y0, vy), y1 = std::max(y1, vy);
    }
  pad_range(x0, x1);
  pad_range(y0, y1);
  Canvas c(pw, ph, use_braille(screen, st));
  // Equal units on both axes, as a path is a shape; a terminal cell is about
  // twice as tall as wide, which the dot grid already accounts for.
  const double sx = (c.width() - 1) / (x1 - x0), sy = (c.height() - 1) / (y1 - y0), s = std::min(sx, sy);
  const double ox = 0.5 * ((c.width() - 1) - s * (x1 - x0)), oy = 0.5 * ((c.height() - 1) - s * (y1 - y0));
  int attrs[4] = {0};
  char glyphs[4] = {' '};
  for (int i = 0; i < 3; ++i) attrs[i + 1] = st.traces[size_t(i)].attr, glyphs[i + 1] = st.traces[size_t(i)].glyph;
  for (uint8_t si = 0; si < 3; ++si) {
    bool have = false;
    int px = 0, py = 0;
    for (const Sample& smp : samples) {
      const double vx = field_value(smp, fields[si], ax), vy = field_value(smp, fields[si], ay);
      if (!std::isfinite(vx) || !std::isfinite(vy)) continue;
      const int cx = int(std::lround(ox + (vx - x0) * s));
      const int cy = int(std::lround(c.height() - 1 - (oy + (vy - y0) * s)));
      if (have) c.line(px, py, cx, cy, uint8_t(si + 1));
      else c.dot(cx, cy, uint8_t(si + 1));
      px = cx, py = cy, have = true;
    }
  }
  c.draw(y + 1, x, attrs, glyphs);
  put(y + h - 1, x, fmt::format("x {:.3g}..{:.3g}  y {:.3g}..{:.3g}", x0, x1, y0, y1), w, screen.attr(Role::Dim));
}

}  // namespace nlsoft::console::tui
