#include "app/tui/plot_view.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "app/tui/canvas.hpp"
#include "app/tui/curses.hpp"

namespace nlsoft::console::tui {

namespace tf = protocol::telemetry_field;

namespace {

constexpr int kLabelWidth = 9;
const char kGlyphs[] = {' ', '.', '+', '*'};

struct Series {
  uint8_t field;
  const char* name;
  Role role;
};
constexpr Series kSeries[] = {{tf::kYRef, "ref", Role::Ref}, {tf::kYHat, "hat", Role::Hat}, {tf::kYTrue, "true", Role::True}};

const float* values(const Sample& s, uint8_t field) {
  return field == tf::kYRef ? s.y_ref() : field == tf::kYHat ? s.y_hat() : s.y_true();
}

void attrs_of(const Screen& screen, int* attrs) {
  attrs[0] = 0;
  for (int i = 0; i < 3; ++i) attrs[i + 1] = screen.attr(kSeries[i].role);
}

void legend(const Screen& screen, int y, int x, int w, const std::string& title) {
  put(y, x, title, w, screen.attr(Role::KeyName));
  int cx = x + int(title.size()) + 2;
  for (int i = 0; i < 3; ++i) {
    const std::string item = fmt::format("{} {}", screen.utf8() ? "\u2501" : std::string(1, kGlyphs[i + 1]), kSeries[i].name);
    put(y, cx, item, x + w - cx, screen.attr(kSeries[i].role));
    cx += int(kSeries[i].name == std::string("true") ? 7 : 6);
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

}  // namespace

void draw_time_plots(const Screen& screen, int y, int x, int h, int w, const std::vector<Sample>& samples,
                     double window_steps) {
  if (samples.empty()) {
    put(y + h / 2, x + 2, "no telemetry yet: start a run (F5) to see y_ref, y_hat and y_true", w - 4,
        screen.attr(Role::Dim));
    return;
  }
  const int n = samples.back().n;
  if (n <= 0 || h < 3 * n) {
    put(y, x, "window too small for the plots", w, screen.attr(Role::Warn));
    return;
  }
  int attrs[4];
  attrs_of(screen, attrs);
  const double t1 = samples.back().step, t0 = t1 - window_steps;
  const int strip = h / n;
  for (int axis = 0; axis < n; ++axis) {
    const int sy = y + axis * strip;
    const int ph = strip - 1, pw = w - kLabelWidth;
    if (ph < 2 || pw < 8) continue;
    double lo = INFINITY, hi = -INFINITY;
    for (const Sample& s : samples) {
      if (s.step < t0) continue;
      for (const Series& se : kSeries) {
        if (!s.has(se.field)) continue;
        const double v = values(s, se.field)[axis];
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
      }
    }
    pad_range(lo, hi);
    legend(screen, sy, x, w, fmt::format("y{}", axis));
    put(sy + 1, x, fmt::format("{:>8.4g}", hi), kLabelWidth - 1, screen.attr(Role::Dim));
    put(sy + ph, x, fmt::format("{:>8.4g}", lo), kLabelWidth - 1, screen.attr(Role::Dim));
    attrset(screen.attr(Role::Border));
    mvvline(sy + 1, x + kLabelWidth - 1, screen.utf8() ? ACS_VLINE : '|', ph);
    attrset(A_NORMAL);
    Canvas c(pw, ph, screen.utf8());
    for (uint8_t si = 0; si < 3; ++si) {
      const Series& se = kSeries[si];
      bool have = false;
      int px = 0, py = 0;
      for (const Sample& s : samples) {
        if (s.step < t0 || !s.has(se.field)) continue;
        const double v = values(s, se.field)[axis];
        if (!std::isfinite(v)) continue;
        const int cx = int(std::lround((double(s.step) - t0) / std::max(1.0, window_steps) * (c.width() - 1)));
        const int cy = int(std::lround((hi - v) / (hi - lo) * (c.height() - 1)));
        if (have) c.line(px, py, cx, cy, uint8_t(si + 1));
        else c.dot(cx, cy, uint8_t(si + 1));
        px = cx, py = cy, have = true;
      }
    }
    c.draw(sy + 1, x + kLabelWidth, attrs, kGlyphs);
  }
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
  legend(screen, y, x, w, fmt::format("path y{} \u2192 / y{} \u2191  (x: change axes)", ax, ay));
  const int ph = h - 1, pw = w;
  if (ph < 3 || pw < 6) return;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Sample& s : samples)
    for (const Series& se : kSeries) {
      if (!s.has(se.field)) continue;
      const float* v = values(s, se.field);
      if (!std::isfinite(v[ax]) || !std::isfinite(v[ay])) continue;
      x0 = std::min(x0, double(v[ax])), x1 = std::max(x1, double(v[ax]));
      y0 = std::min(y0, double(v[ay])), y1 = std::max(y1, double(v[ay]));
    }
  pad_range(x0, x1);
  pad_range(y0, y1);
  Canvas c(pw, ph, screen.utf8());
  // Equal units on both axes, as a path is a shape; a terminal cell is about
  // twice as tall as wide, which the dot grid already accounts for.
  const double sx = (c.width() - 1) / (x1 - x0), sy = (c.height() - 1) / (y1 - y0), s = std::min(sx, sy);
  const double ox = 0.5 * ((c.width() - 1) - s * (x1 - x0)), oy = 0.5 * ((c.height() - 1) - s * (y1 - y0));
  int attrs[4];
  attrs_of(screen, attrs);
  for (uint8_t si = 0; si < 3; ++si) {
    const Series& se = kSeries[si];
    bool have = false;
    int px = 0, py = 0;
    for (const Sample& smp : samples) {
      if (!smp.has(se.field)) continue;
      const float* v = values(smp, se.field);
      if (!std::isfinite(v[ax]) || !std::isfinite(v[ay])) continue;
      const int cx = int(std::lround(ox + (double(v[ax]) - x0) * s));
      const int cy = int(std::lround(c.height() - 1 - (oy + (double(v[ay]) - y0) * s)));
      if (have) c.line(px, py, cx, cy, uint8_t(si + 1));
      else c.dot(cx, cy, uint8_t(si + 1));
      px = cx, py = cy, have = true;
    }
  }
  c.draw(y + 1, x, attrs, kGlyphs);
  put(y + h - 1, x, fmt::format("x {:.3g}..{:.3g}  y {:.3g}..{:.3g}", x0, x1, y0, y1), w, screen.attr(Role::Dim));
}

}  // namespace nlsoft::console::tui
