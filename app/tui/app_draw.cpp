// The screen, redrawn whole: title, plots, the side panel with the focus,
// the message line, the link's status, the key bar, and the boxes over them.
#include <fmt/format.h>

#include <algorithm>

#include "app/record/run_metrics.hpp"
#include "app/tui/app.hpp"
#include "app/tui/confirm_view.hpp"
#include "app/tui/curses.hpp"
#include "app/tui/fit_text.hpp"
#include "app/tui/help_view.hpp"
#include "app/tui/status_bar.hpp"

namespace nlsoft::console::tui {

using host::RigSensor;

namespace {

constexpr int kMinCols = 60, kMinRows = 16;
// From this width the side panel takes two fifths (at least 40 columns);
// below it a narrow one, so an 80-column terminal keeps most of its width
// for the plot.
constexpr int kWideCols = 100;

}  // namespace

void App::draw_title(int w) {
  const auto info = console_.device().info();
  const LinkStats st = console_.session().stats();
  static const char* states[] = {"idle", "RUNNING", "HOLD", "NEUTRAL", "FAULT"};
  std::string run = console_.runs().running()
                        ? fmt::format("run {} {} k={}", console_.runs().current(), st.run_state < 5 ? states[st.run_state] : "?",
                                      console_.runs().samples())
                        : "no run";
  // Narrower than the whole title: the fields least needed while working
  // go first (the program's name, the firmware's version) while the
  // database's path would keep less than its file name and a few folders;
  // then the path loses its middle folders; the run's state stays.
  std::vector<Field> fields = {{"nlsoft-console", 0},
                               {fmt::format("{} {}.{}.{}", info.firmware, info.fw_major, info.fw_minor, info.fw_patch), 1},
                               {fmt::format("{} n={} m={} {} Hz", console_.device().rig_label(), info.n, info.m, info.loop_rate_hz), 3},
                               {run, 4}};
  const std::string db = console_.db_path(), more = screen_.ellipsis();
  const size_t width = size_t(std::max(1, w - 1));
  const size_t least = text_columns(more + db.substr(std::min(db.size(), db.rfind('/') + 1))) + 9;
  size_t room = 0;
  for (;;) {
    size_t used = 4;  // "rec "
    for (const Field& f : fields) used += text_columns(f.text) + 3;
    room = width > used ? width - used : 0;
    if (room >= std::min(least, text_columns(db)) || fields.size() == 1) break;
    fields.erase(std::min_element(fields.begin(), fields.end(),
                                  [](const Field& a, const Field& b) { return a.keep < b.keep; }));
  }
  fields.push_back({"rec " + elide_path(db, std::max<size_t>(room, 1), more), 2});
  fill_row(0, 0, w, screen_.attr(Role::Title));
  put(0, 1, fit_fields(fields, " | ", width, more), int(width), screen_.attr(Role::Title));
}

void App::draw_message_line(int y, int w) {
  if (cmd_.active()) {
    // A value offered (a file name) says that typing replaces it.
    const std::string hint = cmd_.selected() ? cmd_.hint(w / 2) : "";
    const int hw = int(text_columns(hint));
    cmd_.draw(y, 0, hint.empty() ? w : w - hw - 2, 0, screen_.ellipsis());
    if (!hint.empty()) put(y, w - hw, hint, hw, screen_.attr(Role::Pending));
    return;
  }
  fill_row(y, 0, w, 0);
  const MessageLog::Entry e = log_.last();
  const std::pair<std::string, Role> last{e.text, e.role};
  const std::string busy = worker_.busy();
  std::string right = busy.empty() ? "" : "[" + busy + "...]";
  {
    std::lock_guard<std::mutex> lock(ui_mu_);
    if (!busy.empty() && progress_total_ > 0)
      right = fmt::format("[{}: {}/{} steps, {:.0f} %]", progress_what_, progress_done_, progress_total_,
                          100.0 * double(progress_done_) / double(progress_total_));
  }
  const int room = std::max(0, w - int(text_columns(right)) - 1);
  put(y, 0, elide_words(last.first, size_t(room), screen_.ellipsis()), room, screen_.attr(last.second));
  if (!right.empty()) put(y, w - int(right.size()), right, int(right.size()), screen_.attr(Role::Pending));
}

// The link's statistics, led by how the simulator ended while it is down:
// the link is not merely down, and R is the way back.
void App::draw_status(int y, int w) {
  const LinkStats st = console_.session().stats();
  if (!sim_down_.load()) {
    // The firmware sends SENSOR_HEALTH with each sample: an older word is
    // a run that ended, no longer what the chips say.
    const SampleIntake::Health h = console_.samples().health();
    std::string alert;
    if (h.known && h.invalid != 0 && h.received_s_ago < 2.0) {
      std::vector<std::string> names;
      for (const RigSensor& l : console_.rig().sensors) names.push_back(l.name);
      alert = invalid_sensors_words(h.invalid, names);
    }
    draw_status_bar(screen_, y, w, st, console_.session().port(), alert);
    return;
  }
  std::vector<Field> fields = {{" " + sim_gone_, 100}, {"R restarts it", 99}};
  for (const Field& f : status_fields(st, console_.session().port())) fields.push_back(f);
  fill_row(y, 0, w, screen_.attr(Role::Error));
  put(y, 0, fit_fields(fields, " | ", size_t(w), screen_.ellipsis()), w, screen_.attr(Role::Error));
}

// `unmeasured`: the samples shown track a reference without a measured
// output, which the status then says before anything else.
void App::draw_plot_status(int y, int w, bool unmeasured) {
  std::string text = fmt::format(" {} | window {:g} s | ", plot_signal_name(signal_), window_s_);
  if (unmeasured) {
    put(y, 0, fmt::format(" {} | {}", plot_signal_name(signal_), kNoMeasuredOutput), w, screen_.attr(Role::Warn));
    return;
  }
  if (paused_ && end_step_ >= 0 && cursor_step_ >= 0)
    text += fmt::format("PAUSED at {:.2f} s, cursor {:.2f} s  (< > move, Space live)", double(end_step_) / step_rate(),
                        double(cursor_step_) / step_rate());
  else if (paused_ && end_step_ >= 0)
    text += fmt::format("PAUSED at {:.2f} s  (Space live, [ ] scroll, < > cursor, +/- zoom)",
                        double(end_step_) / step_rate());
  else
    text += "live  (p signal, Space pause, +/- zoom, v path)";
  put(y, 0, elide_words(text, size_t(std::max(0, w)), screen_.ellipsis()), w, screen_.attr(paused_ ? Role::Warn : Role::Dim));
}

void App::draw() {
  erase();
  const int rows = screen_.rows(), cols = screen_.cols();
  if (cols < kMinCols || rows < kMinRows) {
    put(0, 0, fmt::format("terminal too small: {}x{}, need {}x{}", cols, rows, kMinCols, kMinRows), cols,
        screen_.attr(Role::Warn));
    put(1, 0, "q quits", cols, 0);
    refresh();
    return;
  }
  draw_title(cols);
  const int right_w = !panel_ ? 0 : cols >= kWideCols ? std::max(40, cols * 2 / 5) : std::max(24, cols * 7 / 20);
  const int left_w = panel_ ? cols - right_w - 1 : cols;
  const int main_h = rows - 4;
  const double rate = step_rate();
  TimeView view;
  view.signal = signal_;
  view.window_steps = window_s_ * rate;
  view.rate_hz = rate;
  view.end_step = paused_ ? end_step_ : -1;
  view.cursor_step = paused_ ? cursor_step_ : -1;
  plot_columns_ = std::max(2, left_w - kTimePlotLabelWidth);
  std::shared_ptr<const RunSeries> overlay;
  {
    std::lock_guard<std::mutex> lock(ui_mu_);
    overlay = overlay_;
    view.overlay_id = overlay_id_;
  }
  view.overlay = overlay.get();
  // Live, only the window is copied (at most one sample per step).
  const std::vector<Sample> live =
      paused_ ? std::vector<Sample>{} : console_.samples().live().snapshot(size_t(std::min(1e9, view.window_steps + 2)));
  const std::vector<Sample>& samples = paused_ ? frozen_ : live;
  // The help covers the screen: nothing is drawn under it, so no plot dot
  // shows beside or through it (and no time goes into plots nobody sees).
  if (help_) {
    draw_message_line(rows - 3, cols);
    draw_status(rows - 2, cols);
    draw_key_bar(screen_, rows - 1, cols, sim_down_.load());
    help_top_ = draw_help(screen_, rows, cols, help_top_);
    std::lock_guard<std::mutex> lock(ui_mu_);
    if (confirming_) draw_confirm(screen_, rows, cols, confirm_title_, confirm_lines_);  // it takes the keys: it shows
    refresh();
    return;
  }
  if (path_view_) {
    // The newest 4096 samples make the shape; copying all that is kept
    // 25 times a second would cost 100 MB/s for nothing visible.
    draw_path_view(screen_, 1, 0, main_h, left_w, paused_ ? frozen_ : console_.samples().live().snapshot(4096), ax_, ay_);
  } else {
    // The convergence view takes the bottom of the plot pane while shown.
    const int tune_h = show_tune_ && !tune_.empty() ? std::min(10, (main_h - 1) / 3) : 0;
    draw_time_plots(screen_, 1, 0, main_h - 1 - tune_h, left_w, samples, view);
    if (tune_h > 0) draw_tune_view(screen_, main_h - tune_h, 0, tune_h, left_w, tune_.snapshot());
    const bool unmeasured = !samples.empty() && samples.back().has(protocol::telemetry_field::kYRef) &&
                            !samples.back().has(protocol::telemetry_field::kYTrue);
    draw_plot_status(rows - 4, left_w, unmeasured);
  }
  if (panel_) {
    attrset(screen_.attr(Role::Border));
    mvvline(1, left_w, screen_.utf8() ? ACS_VLINE : '|', main_h);
    attrset(A_NORMAL);
    const int rx = left_w + 1;
    switch (focus_) {
      case Focus::Params: params_.draw(screen_, 1, rx, main_h, right_w, true); break;
      case Focus::Ref: refs_.draw(screen_, 1, rx, main_h, right_w, true); break;
      case Focus::Runs: runs_.draw(screen_, 1, rx, main_h, right_w, true); break;
      case Focus::Log: log_.draw(screen_, 1, rx, main_h, right_w, true, log_back_); break;
    }
  }
  draw_message_line(rows - 3, cols);
  draw_status(rows - 2, cols);
  draw_key_bar(screen_, rows - 1, cols, sim_down_.load());
  {
    std::lock_guard<std::mutex> lock(ui_mu_);
    if (confirming_) draw_confirm(screen_, rows, cols, confirm_title_, confirm_lines_);
  }
  refresh();
}

}  // namespace nlsoft::console::tui
