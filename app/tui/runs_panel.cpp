#include "app/tui/list_cursor.hpp"
#include "app/tui/runs_panel.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "app/record/csv_export.hpp"
#include "app/record/loop_rate.hpp"
#include "app/record/run_metrics.hpp"
#include "host/files/printable.hpp"
#include "app/tui/curses.hpp"
#include "app/tui/fit_text.hpp"

namespace nlsoft::console::tui {

using host::printable;

namespace {
std::vector<std::string> describe(const RunRow& r, const RunMetrics& m) {
  const TrackingMetrics& t = m.has_true ? m.truth : m.predicted;
  std::string rmse;
  for (double v : t.rmse) rmse += (rmse.empty() ? "" : " ") + fmt::format("{:.4g}", v);
  std::vector<std::string> lines = {
      fmt::format("run {} {} {}", r.id, printable(r.label),
                  r.ended_at.empty() ? "(running or unfinished)" : printable(r.end_reason)),
      // An identification run has no reference to score against.
      r.kind == "ident" ? std::string("identification run: no reference, no tracking figures")
                        : fmt::format("rmse [{}]  nrmse {}  max {:.4g}", rmse, nrmse_words(t.nrmse), t.max_error),
      r.kind == "ident" ? loop_rate_text(m)
                        : fmt::format("{}, compute p50 {:.1f} p99 {:.1f} us", loop_rate_text(m), m.compute_p50_us,
                                      m.compute_p99_us),
      fmt::format("{} samples, {:.1f} s, lost {}, gaps {}", m.samples, m.duration_s, m.lost_frames, m.gaps),
  };
  // Next to the figures it qualifies.
  if (!m.has_true && m.samples > 0 && r.kind != "ident") lines.insert(lines.begin() + 1, kNoMeasuredOutput);
  return lines;
}
}  // namespace

void RunsPanel::reload() {
  worker_.post("reading runs", [this] {
    try {
      RunStore store(console_.db_path());
      auto runs = store.list();
      std::reverse(runs.begin(), runs.end());
      std::lock_guard<std::mutex> lock(mu_);
      runs_ = std::move(runs);
      if (selected_ >= runs_.size()) selected_ = runs_.empty() ? 0 : runs_.size() - 1;
    } catch (const std::exception& e) {
      ui_.message(e.what(), Role::Error);
    }
  });
}

void RunsPanel::show(int64_t id) {
  worker_.post("computing metrics", [this, id] {
    try {
      RunStore store(console_.db_path());
      const auto lines = describe(store.run(id), run_metrics(store, id));
      std::lock_guard<std::mutex> lock(mu_);
      detail_ = lines;
    } catch (const std::exception& e) {
      ui_.message(e.what(), Role::Error);
    }
  });
}

bool RunsPanel::key(int ch) {
  // unique_lock: 'R' releases it around reload().
  std::unique_lock<std::mutex> lock(mu_);
  const size_t n = runs_.size();
  if (move_cursor(ch, selected_, n)) return true;
  switch (ch) {
    case '\n':
    case '\r':
    case KEY_ENTER:
      if (selected_ < n) show(runs_[selected_].id);
      return true;
    case 'm':
      if (selected_ < n) {
        marked_ = runs_[selected_].id;
        ui_.message(fmt::format("run {} marked; select another and press c to compare", marked_));
      }
      return true;
    case 'c':
      if (selected_ < n && marked_) {
        const int64_t a = marked_, b = runs_[selected_].id;
        worker_.post("comparing", [this, a, b] {
          try {
            RunStore store(console_.db_path());
            const RunMetrics ma = run_metrics(store, a), mb = run_metrics(store, b);
            std::vector<std::string> lines = {fmt::format("{:<12} {:>12} {:>12}", "", "run " + std::to_string(a),
                                                          "run " + std::to_string(b))};
            for (const char* k : {"rmse", "nrmse", "max_error", "loop_rate_hz", "compute_p99_us", "lost_frames", "samples"})
              lines.push_back(fmt::format("{:<12} {:>12.5g} {:>12.5g}", k, metric_value(ma, k).value_or(0),
                                          metric_value(mb, k).value_or(0)));
            std::lock_guard<std::mutex> l(mu_);
            detail_ = lines;
          } catch (const std::exception& e) {
            ui_.message(e.what(), Role::Error);
          }
        });
      } else {
        ui_.message("mark a run with m first", Role::Warn);
      }
      return true;
    case 'e':
      if (selected_ < n) {
        const int64_t id = runs_[selected_].id;
        ui_.prompt("export CSV to: ", fmt::format("run{}.csv", id), [this, id](const std::string& path) {
          if (path.empty()) return;
          worker_.post("exporting", [this, id, path] {
            try {
              RunStore store(console_.db_path());
              const size_t rows = export_run_csv(store, id, path);
              ui_.message(fmt::format("run {}: {} samples written to {}", id, rows, path), Role::Ok);
            } catch (const std::exception& e) {
              ui_.message(e.what(), Role::Error);
            }
          });
        });
      }
      return true;
    case 'R':
      lock.unlock();
      reload();
      lock.lock();
      return true;
  }
  return false;
}

void RunsPanel::draw(const Screen& screen, int y, int x, int h, int w, bool focused) {
  std::lock_guard<std::mutex> lock(mu_);
  put(y, x, fmt::format(" Runs ({}) ", runs_.size()), w, screen.attr(focused ? Role::Title : Role::KeyName));
  const int list_h = std::max(1, h - 7);
  if (selected_ < top_) top_ = selected_;
  if (selected_ >= top_ + size_t(list_h)) top_ = selected_ - size_t(list_h) + 1;
  for (int i = 0; i < list_h && top_ + size_t(i) < runs_.size(); ++i) {
    const RunRow& r = runs_[top_ + size_t(i)];
    const bool sel = focused && top_ + size_t(i) == selected_;
    const std::string line = fmt::format("{}{:>4} {:<19.19} {:>7} lost {:<3} {}", r.id == marked_ ? '*' : ' ', r.id,
                                         printable(r.started_at), r.samples, r.lost_frames, printable(r.label));
    fill_row(y + 1 + i, x, w, sel ? screen.attr(Role::Selected) : 0);
    put(y + 1 + i, x, line, w, sel ? screen.attr(Role::Selected) : 0);
  }
  for (size_t i = 0; i < detail_.size() && int(i) < 5; ++i)
    put(y + h - 6 + int(i), x + 1, elide_words(detail_[i], size_t(std::max(0, w - 2)), screen.ellipsis()), w - 2,
        screen.attr(Role::Normal));
  put(y + h - 1, x,
      fit_hints({"Enter metrics", "m mark", "c compare", "e export", "R reread"}, size_t(w), screen.ellipsis()), w,
      screen.attr(Role::Dim));
}

}  // namespace nlsoft::console::tui
