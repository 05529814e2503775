#include "app/tui/tune_view.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "app/tui/canvas.hpp"
#include "app/tui/curses.hpp"

namespace nlsoft::console::tui {

void TuneTrace::add(const TuneEvaluation& e) {
  std::lock_guard<std::mutex> lock(mu_);
  if (e.eval <= 1) evals_.clear();
  evals_.push_back(e);
}

std::vector<TuneEvaluation> TuneTrace::snapshot() const {
  std::lock_guard<std::mutex> lock(mu_);
  return evals_;
}

bool TuneTrace::empty() const {
  std::lock_guard<std::mutex> lock(mu_);
  return evals_.empty();
}

void draw_tune_view(const Screen& screen, int y, int x, int h, int w, const std::vector<TuneEvaluation>& evals) {
  if (h < 3 || w < 20 || evals.empty()) return;
  const TuneEvaluation& last = evals.back();
  std::string best_point;
  for (const auto& e : evals)
    if (e.eval == last.best_eval) best_point = e.point;
  const std::string head =
      std::isfinite(last.best)
          ? fmt::format(" tune: eval {}{}  best {:.4g} (eval {}) {}", last.eval,
                        last.budget > 0 ? fmt::format("/{}", last.budget) : "", last.best, last.best_eval, best_point)
          : fmt::format(" tune: eval {}{}  no success yet", last.eval, last.budget > 0 ? fmt::format("/{}", last.budget) : "");
  fill_row(y, x, w, screen.attr(Role::Title));
  put(y, x, head, w, screen.attr(Role::Title));
  // A log axis when every value is positive: objectives fall by decades.
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& e : evals)
    if (std::isfinite(e.objective)) lo = std::min(lo, e.objective), hi = std::max(hi, e.objective);
  const bool any = std::isfinite(lo);
  const bool logy = any && lo > 0;
  auto ty = [&](double v) { return logy ? std::log10(v) : v; };
  double a = any ? ty(lo) : 0, b = any ? ty(hi) : 1;
  if (!(b > a)) a -= 0.5, b += 0.5;
  constexpr int kLabel = 9;
  const int ph = h - 1, pw = w - kLabel;
  if (pw < 6) return;
  put(y + 1, x, fmt::format("{:>8.3g}", any ? hi : 1.0), kLabel - 1, screen.attr(Role::Dim));
  put(y + ph, x, fmt::format("{:>8.3g}", any ? lo : 0.0), kLabel - 1, screen.attr(Role::Dim));
  Canvas c(pw, ph, screen.utf8());
  const int n = std::max(2, last.budget > 0 ? last.budget : last.eval);
  auto cx = [&](int eval) { return int(std::lround(double(eval - 1) / double(n - 1) * (c.width() - 1))); };
  auto cy = [&](double v) { return int(std::lround((b - ty(v)) / (b - a) * (c.height() - 1))); };
  bool have = false;
  int px = 0, py = 0;
  for (const auto& e : evals) {
    if (std::isfinite(e.objective)) c.dot(cx(e.eval), cy(e.objective), 1);
    else c.dot(cx(e.eval), c.height() - 1, 3);
    if (!std::isfinite(e.best)) continue;
    const int x1 = cx(e.eval), y1 = cy(e.best);
    if (have) c.line(px, py, x1, py, 2), c.line(x1, py, x1, y1, 2);
    else c.dot(x1, y1, 2);
    px = x1, py = y1, have = true;
  }
  const int attrs[4] = {0, screen.series_attr(0), screen.attr(Role::Ok), screen.attr(Role::Error)};
  const char glyphs[4] = {' ', '.', '*', 'x'};
  c.draw(y + 1, x + kLabel, attrs, glyphs);
}

}  // namespace nlsoft::console::tui
