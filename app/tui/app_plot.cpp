// The plot's view: its signal, a paused copy scrolled and read at a cursor
// (older samples read back from the database), a recorded run under it.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>

#include "host/files/printable.hpp"
#include "app/tui/app.hpp"

namespace nlsoft::console::tui {

using host::printable;

void App::plot_command(const std::string& args) {
  const size_t a = args.find_first_not_of(' ');
  const std::string name = a == std::string::npos ? "" : args.substr(a, args.find_last_not_of(' ') - a + 1);
  PlotSignal s;
  if (name.empty()) {
    message(fmt::format("plot SIGNAL: {} (now {}; p cycles)", plot_signal_names(), plot_signal_name(signal_)), Role::Warn);
  } else if (!plot_signal_from_name(name, &s)) {
    message(fmt::format("plot: '{}' is not a signal; use {}", name, plot_signal_names()), Role::Error);
  } else {
    signal_ = s;
    path_view_ = false;
  }
}

void App::overlay_command(const std::string& args) {
  const size_t a = args.find_first_not_of(' ');
  const std::string arg = a == std::string::npos ? "" : args.substr(a, args.find_last_not_of(' ') - a + 1);
  if (arg == "off") {
    std::lock_guard<std::mutex> lock(ui_mu_);
    overlay_.reset();
    overlay_id_ = 0;
    message("overlay removed");
    return;
  }
  char* end = nullptr;
  const long long id = std::strtoll(arg.c_str(), &end, 10);
  if (arg.empty() || *end != '\0' || id <= 0) {
    message("overlay ID: a recorded run under the live plot (F4 lists them); overlay off removes it", Role::Error);
    return;
  }
  worker_.post(fmt::format("loading run {}", id), [this, id] {
    try {
      RunStore store(console_.db_path());
      const RunRow row = store.run(id);
      auto series = std::make_shared<const RunSeries>(store.series(id));
      {
        std::lock_guard<std::mutex> lock(ui_mu_);
        overlay_ = std::move(series);
        overlay_id_ = id;
      }
      message(fmt::format("overlay: run {}{} under the live plot, step for step from its start ('o'); overlay off "
                          "removes it",
                          id, row.label.empty() ? "" : " (" + printable(row.label) + ")"),
              Role::Ok);
    } catch (const std::exception& e) {
      message(std::string("overlay: ") + e.what(), Role::Error);
    }
  });
}

double App::step_rate() {
  const double r = console_.session().stats().loop_rate_hz;
  return r > 0 ? r : std::max(1.0, double(console_.device().info().loop_rate_hz));
}

void App::pause_plot(bool on) {
  paused_ = on;
  if (on) {
    frozen_ = console_.samples().live().snapshot(SampleIntake::kLiveSamples);
    end_step_ = frozen_.empty() ? -1 : int64_t(frozen_.back().step);
    const auto last = console_.runs().last();
    frozen_run_ = console_.runs().running() ? console_.runs().current() : last ? last->run_id : 0;
  } else {
    frozen_.clear();
    end_step_ = -1;
    cursor_step_ = -1;
    frozen_run_ = 0;
  }
}

void App::load_older_samples() {
  if (loading_older_ || frozen_run_ == 0) return;
  loading_older_ = true;
  const int64_t run = frozen_run_;
  const uint64_t before = frozen_.front().k;
  message(fmt::format("reading run {}'s samples before #{} from the database...", run, before));
  worker_.post("loading older samples", [this, run, before] {
    std::deque<Sample> chunk;
    try {
      RunStore store(console_.db_path());
      store.for_each_sample(run, [&](const Sample& smp) {
        if (smp.k >= before) return;
        chunk.push_back(smp);
        if (chunk.size() > SampleIntake::kLiveSamples) chunk.pop_front();
      });
    } catch (const std::exception& e) {
      message(std::string("older samples: ") + e.what(), Role::Error);
    }
    std::lock_guard<std::mutex> lock(ui_mu_);
    older_.assign(chunk.begin(), chunk.end());
    older_ready_ = true;
  });
}

// On the UI thread: what the worker read goes in front of the paused
// samples, if the view is still paused on the same run.
void App::merge_older_samples() {
  std::vector<Sample> older;
  {
    std::lock_guard<std::mutex> lock(ui_mu_);
    if (!older_ready_) return;
    older_ready_ = false;
    older.swap(older_);
  }
  loading_older_ = false;
  if (!paused_ || frozen_.empty()) return;
  const uint64_t before = frozen_.front().k;
  while (!older.empty() && older.back().k >= before) older.pop_back();
  if (older.empty()) {
    message(fmt::format("run {} has no samples before those shown", frozen_run_));
    return;
  }
  message(fmt::format("{} older samples of run {} read from the database: [ scrolls on", older.size(), frozen_run_),
          Role::Ok);
  frozen_.insert(frozen_.begin(), older.begin(), older.end());
}

void App::move_cursor(int columns) {
  if (!paused_) pause_plot(true);
  if (frozen_.empty()) return;
  cursor_step_ = move_time_cursor(cursor_step_, end_step_, window_s_ * step_rate(), plot_columns_, columns);
}

// Moves the paused view by a number of windows, within what was kept.
void App::scroll_plot(double windows) {
  if (!paused_) pause_plot(true);
  if (frozen_.empty()) return;
  const double window = window_s_ * step_rate();
  // Back until the oldest sample kept is at the right edge.
  const int64_t first = int64_t(frozen_.front().step), last = int64_t(frozen_.back().step);
  const int64_t want = end_step_ + int64_t(std::llround(windows * window));
  if (want - int64_t(window) < first && frozen_.front().k > 0) load_older_samples();
  end_step_ = std::max(first, std::min(last, want));
  if (cursor_step_ >= 0)  // the cursor stays on screen, at the same time when it can
    cursor_step_ = std::max(end_step_ - int64_t(window), std::min(end_step_, cursor_step_));
}

}  // namespace nlsoft::console::tui
