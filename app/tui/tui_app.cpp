#include "app/tui/tui_app.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <deque>
#include <mutex>

#include "app/printable.hpp"
#include "app/record/loop_rate.hpp"
#include "app/record/run_store.hpp"
#include "app/script/script_runner.hpp"
#include "app/tui/completion.hpp"
#include "app/tui/exit_summary.hpp"
#include "app/tui/fit_text.hpp"
#include "app/tui/curses.hpp"
#include "app/tui/line_edit.hpp"
#include "app/tui/message_log.hpp"
#include "app/tui/param_panel.hpp"
#include "app/tui/plot_view.hpp"
#include "app/tui/ref_panel.hpp"
#include "app/tui/runs_panel.hpp"
#include "app/tui/screen.hpp"
#include "app/tui/status_bar.hpp"
#include "app/tui/tune_view.hpp"
#include "app/tui/ui.hpp"
#include "app/tui/worker.hpp"

namespace nlsoft::console {

namespace tui {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kMinCols = 60, kMinRows = 16;
// From this width the side panel takes two fifths (at least 40 columns);
// below it a narrow one, so an 80-column terminal keeps most of its width
// for the plot.
constexpr int kWideCols = 100;

const char* const kHelp[] = {
    "nlsoft-console keys",
    "",
    "  F1 ?      this help: Up/Down/PgUp/PgDn scroll it, any other key closes it",
    "            (Esc, ?, F1, q, Enter or Space only close)",
    "  F2 F3 F4  focus parameters / reference / runs (Tab cycles)",
    "  F9        messages with their times (Up/Down/PgUp scroll back); also in <db>.session.log",
    "  F5        start a run (recorded)     F6  stop the run",
    "  F7        hold / resume              F8  actuators neutral",
    "  v         time plots <-> 2-D path    x   change the path's axes",
    "  w         hide / show the side panel (the plot takes the whole width);",
    "            F2 F3 F4 F9 show it again",
    "  p         plot signal: y, u, cost, iter, compute, ident (u, y, sensors)  (or :plot u)",
    "  :overlay ID  a recorded run under the live plot ('o'); :overlay off",
    "  + -       zoom in (shorter window) / out",
    "  t         the tuning view under the plot on/off (:tune shows it)",
    "  Space     pause the plot (recording goes on)   [ ]  scroll back / forward",
    "  < >       time cursor on a paused plot: the readout gives the values at it",
    "  :         command line: the script commands (set, get, ref, run, expect, ...);",
    "            Tab completes commands, parameter names and options",
    "  q F10     quit (asks first while a run is active)",
    "  R         with --sim, once the simulator has ended (killed, crashed): start it again and",
    "            reconnect (the key bar shows R Restart meanwhile)",
    "",
    "Parameters: Up/Down select, Enter edit in place (Esc cancels), u undo,",
    "            S save to a file, L load one (shows the diff before sending),",
    "            R reread, A send this session's edits again (after a firmware reset)",
    "Reference:  Left/Right kind, Enter edit a value, a send (CSV: upload)",
    "Runs:       Enter metrics, m mark, c compare with the marked run, e export CSV",
};

class App : public Ui {
 public:
  App(LiveConsole& console, Screen& screen)
      : console_(console),
        screen_(screen),
        log_(session_log_path(console.db_path())),
        worker_([this](const std::string& s) { message(s, Role::Error); }),
        params_(console, worker_, *this),
        refs_(console, worker_, *this),
        runs_(console, worker_, *this),
        runner_(
            console, [this](const std::string& s) { message(s); },
            [this](const std::string& what, size_t done, size_t total) {
              // The worker reports an identification run's steps; the UI
              // thread reads them for the message line.
              std::lock_guard<std::mutex> lock(ui_mu_);
              progress_what_ = what;
              progress_done_ = done;
              progress_total_ = total;
            }) {
    // Before any command runs: the worker reports each evaluation of a
    // `:tune` here, the UI thread draws a copy.
    runner_.set_tune_observer([this](const TuneEvaluation& e) {
      tune_.add(e);
      show_tune_ = true;
    });
    cmd_.set_history(&history_);
    cmd_.set_completer([this](const std::string& left) {
      // The same editor asks for file names (S, L): those are not commands.
      if (cmd_.prompt() != ":") return std::make_pair(left, std::vector<std::string>{});
      std::vector<std::string> names;
      for (const ParamInfo& p : console_.device().catalog()->all()) names.push_back(p.name);
      Completion c = complete_command(left, names);
      return std::make_pair(c.text, c.candidates);
    });
    console_.set_notify([this](const std::string& s) { message(s, Role::Warn); });
    params_.reload();
    runs_.reload();
    if (const UdpStream* u = console_.udp())
      message(fmt::format("streaming every telemetry sample to {} (UDP, JSON)", u->target()), Role::Ok);
    const auto info = console_.device().info();
    message(fmt::format("connected to {} {}.{}.{}: F5 starts a run, F1 help", info.firmware, info.fw_major,
                        info.fw_minor, info.fw_patch),
            Role::Ok);
  }
  ~App() override { shutdown(); }

  int loop();

  void message(const std::string& text, Role role = Role::Normal) override { log_.add(text, role); }
  void prompt(const std::string& label, const std::string& initial,
              std::function<void(const std::string&)> done) override {
    std::lock_guard<std::mutex> lock(ui_mu_);
    pending_prompt_ = {label, initial, std::move(done)};
    has_pending_prompt_ = true;
  }
  void confirm(const std::string& title, std::vector<std::string> lines, std::function<void()> yes) override {
    std::lock_guard<std::mutex> lock(ui_mu_);
    confirm_title_ = title;
    confirm_lines_ = std::move(lines);
    confirm_yes_ = std::move(yes);
    confirming_ = true;
  }

 private:
  enum class Focus { Params, Ref, Runs, Log };
  struct PromptRequest {
    std::string label, initial;
    std::function<void(const std::string&)> done;
  };

  bool handle(int ch);  // false: quit
  void focus(Focus f);
  void draw();
  void draw_title(int w);
  void draw_message_line(int y, int w);
  void draw_confirm(int rows, int cols);
  void draw_help(int rows, int cols);
  void start_run();
  void stop_run();
  void check_simulator();
  void restart_simulator();
  void command(const std::string& line);
  void plot_command(const std::string& args);
  void overlay_command(const std::string& args);
  void pause_plot(bool on);
  void scroll_plot(double windows);
  void move_cursor(int columns);
  void load_older_samples();
  void merge_older_samples();
  void draw_plot_status(int y, int w, bool unmeasured);
  void draw_status(int y, int w);
  double step_rate();  // control steps per second, measured when known
  void shutdown();

  LiveConsole& console_;
  Screen& screen_;
  // Before the worker: its error reports are messages. Any thread may add
  // to it until shutdown() has joined the worker and detached the notify.
  MessageLog log_;
  size_t log_back_ = 0;  // log pane: entries scrolled back from the newest
  // Worker tasks use every member below and message() (log_); the worker
  // is therefore stopped and joined in shutdown(), before any member is
  // destroyed, whatever the declaration order.
  Worker worker_;
  ParamPanel params_;
  RefPanel refs_;
  RunsPanel runs_;
  ScriptRunner runner_;
  TuneTrace tune_;
  std::atomic<bool> show_tune_{false};
  Focus focus_ = Focus::Params;
  bool path_view_ = false, help_ = false;
  bool panel_ = true;  // w: the side panel (parameters, reference, runs, messages) shown
  int ax_ = 0, ay_ = 1;
  double window_s_ = 10;
  PlotSignal signal_ = PlotSignal::Y;
  // A paused plot draws from a copy taken at the pause, so the view holds
  // still while telemetry (and the recording) goes on; end_step_ is its
  // right edge, moved by [ and ].
  // `:overlay ID`: a recorded run under the live plot, loaded by the worker.
  std::shared_ptr<const RunSeries> overlay_;  // under ui_mu_
  int64_t overlay_id_ = 0;                    // under ui_mu_
  bool paused_ = false;
  std::vector<Sample> frozen_;
  int64_t end_step_ = -1;
  // Scrolling back past the oldest sample kept in memory reads the run's
  // older samples from the database, a live buffer's worth at a time: the
  // worker loads them into older_ (under ui_mu_), the UI thread prepends
  // them to frozen_, which only it touches.
  int64_t frozen_run_ = 0;  // the run the paused samples belong to; 0: none
  bool loading_older_ = false;
  bool older_ready_ = false;        // under ui_mu_
  std::vector<Sample> older_;       // under ui_mu_
  int64_t cursor_step_ = -1;  // < >: the time the paused plot's readout reads
  int plot_columns_ = 80;     // of the last drawn time plot, for the cursor's step
  int help_top_ = 0;          // first help line shown (a short terminal scrolls it)
  LineEdit cmd_;  // ':' line and prompts share the message row
  std::vector<std::string> history_;
  std::function<void(const std::string&)> prompt_done_;

  std::mutex ui_mu_;
  bool has_pending_prompt_ = false;
  PromptRequest pending_prompt_;
  bool confirming_ = false;
  std::string confirm_title_;
  std::vector<std::string> confirm_lines_;
  std::function<void()> confirm_yes_;
  bool quit_confirmed_ = false;
  bool shut_down_ = false;
  // A `:ident`'s progress (under ui_mu_): total 0 when none is running.
  std::string progress_what_;
  size_t progress_done_ = 0, progress_total_ = 0;
  uint32_t seen_resets_ = 0;  // console_.firmware_resets() the panel has caught up with
  // The simulator has ended and not been restarted yet (R): set by the UI
  // thread, cleared by the worker's restart.
  std::atomic<bool> sim_down_{false};
  std::string sim_gone_;  // how it ended (UI thread only)
};

// The shutdown order, on quit (q, F10, SIGTERM) and in ~App if loop() threw:
//  1. cancel the `:` command in progress: a timed run is stopped and kept, a
//     wait, sweep or tune returns (ScriptRunner::cancel; a tune still puts
//     the parameters back and saves its best, bounded by the link's timeouts);
//  2. stop and join the worker: the task running finishes (bounded by the
//     link's timeouts), queued ones are dropped; afterwards no other thread
//     touches the panels, the runner or the message log;
//  3. detach the console's notify callback: LiveConsole::say calls it under
//     its mutex, so once set_notify returns the link's threads are done with
//     message();
//  4. stop a run still active (F5) on this thread, so it is kept with an end;
// then the members are destroyed, in any order.
void App::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  runner_.cancel();
  worker_.stop();
  console_.set_notify({});
  if (console_.running()) {
    try {
      console_.stop_run(LiveConsole::interrupted() ? LiveConsole::interrupt_reason() : "stopped at quit");
    } catch (...) {
      // Quitting regardless; the run stays open in the database (ended_at NULL).
    }
  }
}

void App::start_run() {
  worker_.post("starting a run", [this] {
    try {
      const int64_t id = console_.start_run("");
      message(fmt::format("run {} started, recording to {}", id, console_.db_path()), Role::Ok);
    } catch (const std::exception& e) {
      message(e.what(), Role::Error);
    }
  });
}

void App::stop_run() {
  worker_.post("stopping the run", [this] {
    try {
      const RunSummary s = console_.stop_run();
      const TrackingMetrics& t = s.metrics.has_true ? s.metrics.truth : s.metrics.predicted;
      message(fmt::format("run {} stopped: {} samples, nrmse {}, lost {}, {}{}", s.run_id, s.metrics.samples,
                          nrmse_words(t.nrmse),
                          s.metrics.lost_frames, loop_rate_text(s.metrics),
                          s.metrics.has_true || s.metrics.samples == 0 ? "" : std::string("; ") + kNoMeasuredOutput),
              Role::Ok);
    } catch (const std::exception& e) {
      message(e.what(), Role::Error);
    }
    runs_.reload();
  });
}

// Polled by the UI thread: a simulator that ended under the console (kill
// -9, a crash) is said once, with how; the run in progress is ended with
// that reason and its gap, and R offers a new simulator.
void App::check_simulator() {
  if (sim_down_.load()) return;
  const std::string gone = console_.simulator_exit();
  if (gone.empty()) return;
  sim_down_ = true;
  sim_gone_ = gone;
  message(gone + "; R restarts it", Role::Error);
  worker_.post("ending the run", [this, gone] {
    try {
      if (const auto s = console_.end_run_simulator_gone())
        message(fmt::format("{}: run {} ended and kept, {} samples and the gap since ({} lost); R restarts the simulator",
                            gone, s->run_id, s->metrics.samples, s->metrics.lost_frames),
                Role::Error);
    } catch (const std::exception& e) {
      message(e.what(), Role::Error);
    }
    runs_.reload();
  });
}

// The new simulator is started here, on the UI thread, which lives as long
// as the console: a child forked on the worker would be ended with it
// (PR_SET_PDEATHSIG follows the thread). The reconnect is the worker's.
void App::restart_simulator() {
  std::string port;
  try {
    port = console_.respawn_simulator();
  } catch (const std::exception& e) {
    message(std::string("the simulator did not restart: ") + e.what() + "; R tries again", Role::Error);
    return;
  }
  worker_.post("reconnecting to the simulator", [this, port] {
    try {
      console_.reconnect_simulator(port);
      sim_down_ = false;
      message(fmt::format("simulator restarted on {} and connected: F5 starts a run", console_.session().port()),
              Role::Ok);
    } catch (const std::exception& e) {
      message(std::string("the simulator did not restart: ") + e.what() + "; R tries again", Role::Error);
    }
  });
}

void App::command(const std::string& line) {
  if (line.empty()) return;
  if (line == "help") {
    help_ = true;
    return;
  }
  if (line == "plot" || line.rfind("plot ", 0) == 0) {
    plot_command(line.substr(4));
    return;
  }
  if (line == "overlay" || line.rfind("overlay ", 0) == 0) {
    overlay_command(line.substr(7));
    return;
  }
  if (line == "q" || line == "quit") {
    handle('q');
    return;
  }
  try {
    const Command c = parse_command(line, "cmd", 1);
    if (c.kind == Command::Kind::Ident) {
      // What an identification run has to show: its inputs, the measured
      // outputs and the sensors, not a reference it has none of.
      signal_ = PlotSignal::Ident;
      path_view_ = false;
      message("identification run: u, measured y and sensors l plotted (p cycles the plots; F6 stops and keeps it)");
    }
    worker_.post(line, [this, c] {
      try {
        runner_.execute(c, "cmd");
      } catch (const ScriptError& e) {
        message(e.message, Role::Error);
      }
      {
        std::lock_guard<std::mutex> lock(ui_mu_);
        progress_total_ = 0;
      }
      const bool many = c.kind == Command::Kind::Sweep || c.kind == Command::Kind::Tune;
      if (c.kind == Command::Kind::Set || c.kind == Command::Kind::ParamsLoad || c.kind == Command::Kind::ParamsReapply || many)
        params_.reload();
      if (c.kind == Command::Kind::Run || c.kind == Command::Kind::Stop || many) runs_.reload();
    });
  } catch (const ScriptError& e) {
    message(e.message, Role::Error);
  }
}

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
  return r > 0 ? r : std::max(1.0, console_.loop_rate_hz());
}

void App::pause_plot(bool on) {
  paused_ = on;
  if (on) {
    frozen_ = console_.live().snapshot(LiveConsole::kLiveSamples);
    end_step_ = frozen_.empty() ? -1 : int64_t(frozen_.back().step);
    const auto last = console_.last_run();
    frozen_run_ = console_.running() ? console_.current_run() : last ? last->run_id : 0;
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
        if (chunk.size() > LiveConsole::kLiveSamples) chunk.pop_front();
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

bool App::handle(int ch) {
  if (ch == KEY_RESIZE) return true;
  {
    std::unique_lock<std::mutex> lock(ui_mu_);
    if (confirming_) {
      if (ch == 'y' || ch == 'Y') {
        confirming_ = false;
        auto yes = std::move(confirm_yes_);
        lock.unlock();
        if (yes) yes();
      } else if (ch == 'n' || ch == 'N' || ch == 27 || ch == 'q') {
        confirming_ = false;
        message("cancelled: nothing sent");
      }
      return !quit_confirmed_;
    }
  }
  if (help_) {
    // Scroll keys move a help taller than the terminal; any other key
    // closes it, and one that means something else is then handled as if
    // the help had not been open.
    const int page = std::max(1, screen_.rows() - 4);
    if (ch == KEY_UP || ch == KEY_DOWN || ch == KEY_PPAGE || ch == KEY_NPAGE || ch == KEY_HOME || ch == KEY_END) {
      help_top_ = ch == KEY_UP ? help_top_ - 1 : ch == KEY_DOWN ? help_top_ + 1 : ch == KEY_PPAGE ? help_top_ - page
                : ch == KEY_NPAGE ? help_top_ + page : ch == KEY_HOME ? 0 : 1 << 20;
      return true;  // draw_help clamps
    }
    help_ = false;
    if (ch == 27 || ch == '?' || ch == KEY_F(1) || ch == 'q' || ch == '\n' || ch == '\r' || ch == ' ') return true;
  }
  if (cmd_.active()) {
    const auto r = cmd_.key(ch);
    if (r == LineEdit::Result::Done) {
      auto done = std::move(prompt_done_);
      prompt_done_ = nullptr;
      if (done) done(cmd_.text());
      else command(cmd_.text());
    } else if (r == LineEdit::Result::Cancelled) {
      prompt_done_ = nullptr;
    }
    return true;
  }
  const bool panel_editing = (focus_ == Focus::Params && params_.editing()) || (focus_ == Focus::Ref && refs_.editing());
  if (panel_editing) {
    if (focus_ == Focus::Params) params_.key(ch);
    else refs_.key(ch);
    return true;
  }
  if (ch == 'R' && sim_down_.load()) {  // before the panels' own R (reread, rerun)
    restart_simulator();
    return true;
  }
  switch (ch) {
    case 'q':
    case KEY_F(10):
      if (console_.running()) {
        confirm("a run is active: stop it and quit?",
                {console_.recording() ? "the run is stopped and kept in the database"
                                      : "the run is stopped; nothing is kept (--no-record)"},
                [this] { quit_confirmed_ = true; });
        return true;
      }
      return false;
    case KEY_F(1):
    case '?':
      help_ = true;
      help_top_ = 0;
      return true;
    case KEY_F(2): focus(Focus::Params); return true;
    case KEY_F(3): focus(Focus::Ref); return true;
    case KEY_F(4):
      focus(Focus::Runs);
      runs_.reload();
      return true;
    case KEY_F(9):
      focus(Focus::Log);
      log_back_ = 0;
      return true;
    case '\t':
      if (focus_ != Focus::Ref) {
        focus(focus_ == Focus::Params ? Focus::Ref : Focus::Params);
        return true;
      }
      break;
    case KEY_BTAB: focus(focus_ == Focus::Params ? Focus::Runs : focus_ == Focus::Ref ? Focus::Params : Focus::Ref); return true;
    case 'w': panel_ = !panel_; return true;
    case KEY_F(5): start_run(); return true;
    case KEY_F(6):
      // A timed run from the ':' line is ended where it waits; otherwise
      // the stop queues behind whatever the worker is doing.
      if (console_.stop_timed_run()) message("stopping the timed run...");
      else stop_run();
      return true;
    case KEY_F(7): {
      const bool held = console_.session().stats().run_state == uint8_t(protocol::RunState::Hold) ||
                        console_.session().stats().run_state == uint8_t(protocol::RunState::Neutral);
      worker_.post("hold", [this, held] {
        try {
          console_.hold(held ? protocol::HoldMode::Resume : protocol::HoldMode::Hold);
          message(held ? "resumed" : "holding (F7 resumes)", Role::Ok);
        } catch (const std::exception& e) {
          message(e.what(), Role::Error);
        }
      });
      return true;
    }
    case KEY_F(8):
      worker_.post("neutral", [this] {
        try {
          console_.hold(protocol::HoldMode::Neutral);
          message("actuators neutral (F7 resumes)", Role::Ok);
        } catch (const std::exception& e) {
          message(e.what(), Role::Error);
        }
      });
      return true;
    case ':':
      prompt_done_ = nullptr;
      cmd_.start(":");
      return true;
    case 'v': path_view_ = !path_view_; return true;
    case 't':
      if (tune_.empty()) message("no tuning session yet: :tune NAME=LO..HI[:log|:lin] ... (F1 for the options)", Role::Warn);
      else show_tune_ = !show_tune_;
      return true;
    case 'x': {
      const int n = std::max(2, console_.n());
      ay_ = (ay_ + 1) % n;
      if (ay_ == ax_) ax_ = (ax_ + 1) % n, ay_ = (ax_ + 1) % n;
      return true;
    }
    case '+': window_s_ = std::max(0.25, window_s_ / 2); return true;
    case '-': window_s_ = std::min(120.0, window_s_ * 2); return true;
    case 'p':
      signal_ = next_plot_signal(signal_);
      path_view_ = false;
      return true;
    case ' ': pause_plot(!paused_); return true;
    case '[': scroll_plot(-0.5); return true;
    case ']': scroll_plot(0.5); return true;
    case '<':
    case ',': move_cursor(-1); return true;
    case '>':
    case '.': move_cursor(1); return true;
  }
  if (!panel_) return true;  // a hidden panel takes no keys: nothing changes out of sight
  switch (focus_) {
    case Focus::Params: params_.key(ch); break;
    case Focus::Ref: refs_.key(ch); break;
    case Focus::Runs: runs_.key(ch); break;
    case Focus::Log: {
      const size_t page = size_t(std::max(1, screen_.rows() - 8));
      if (ch == KEY_UP || ch == 'k') ++log_back_;
      else if (ch == KEY_DOWN || ch == 'j') log_back_ = log_back_ > 0 ? log_back_ - 1 : 0;
      else if (ch == KEY_PPAGE) log_back_ += page;
      else if (ch == KEY_NPAGE) log_back_ = log_back_ > page ? log_back_ - page : 0;
      else if (ch == KEY_END) log_back_ = 0;
      log_back_ = std::min(log_back_, log_.size());
      break;
    }
  }
  return true;
}

// A panel given the keys is shown; the reference panel opens on the
// reference in force, not on whatever it showed last.
void App::focus(Focus f) {
  if (f == Focus::Ref && (focus_ != Focus::Ref || !panel_)) refs_.show_in_force();
  focus_ = f;
  panel_ = true;
}

void App::draw_title(int w) {
  const auto info = console_.device().info();
  const LinkStats st = console_.session().stats();
  static const char* states[] = {"idle", "RUNNING", "HOLD", "NEUTRAL", "FAULT"};
  std::string run = console_.running()
                        ? fmt::format("run {} {} k={}", console_.current_run(), st.run_state < 5 ? states[st.run_state] : "?",
                                      console_.run_samples())
                        : "no run";
  // Narrower than the whole title: the fields least needed while working
  // go first (the program's name, the firmware's version) while the
  // database's path would keep less than its file name and a few folders;
  // then the path loses its middle folders; the run's state stays.
  std::vector<Field> fields = {{"nlsoft-console", 0},
                               {fmt::format("{} {}.{}.{}", info.firmware, info.fw_major, info.fw_minor, info.fw_patch), 1},
                               {fmt::format("{} n={} m={} {} Hz", console_.rig_label(), info.n, info.m, info.loop_rate_hz), 3},
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
    cmd_.draw(y, 0, hint.empty() ? w : w - hw - 2, 0);
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

void App::draw_confirm(int rows, int cols) {
  const int w = std::min(cols - 4, 90);
  const int h = std::min(rows - 4, int(confirm_lines_.size()) + 4);
  const int y0 = (rows - h) / 2, x0 = (cols - w) / 2;
  // A blank margin round the box: no plot dot touches it, so it reads as a
  // box over the screen, not as more lines of the plot.
  for (int r = -1; r <= h; ++r) fill_row(y0 + r, std::max(0, x0 - 1), std::min(cols, w + 2), 0);
  for (int r = 0; r < h; ++r) fill_row(y0 + r, x0, w, screen_.attr(Role::Selected));
  put(y0, x0 + 1, confirm_title_, w - 2, screen_.attr(Role::Selected) | A_BOLD);
  for (int i = 0; i < h - 4 && size_t(i) < confirm_lines_.size(); ++i)
    put(y0 + 2 + i, x0 + 2, confirm_lines_[size_t(i)], w - 4, screen_.attr(Role::Selected));
  if (int(confirm_lines_.size()) > h - 4)
    put(y0 + h - 2, x0 + 2, fmt::format("... and {} more", int(confirm_lines_.size()) - (h - 4)), w - 4,
        screen_.attr(Role::Selected));
  put(y0 + h - 1, x0 + 1, "y: yes   n/Esc: no", w - 2, screen_.attr(Role::Selected) | A_BOLD);
}

namespace {

// A help line in pieces of at most `width` columns; continuations are
// indented to `indent` (the column where the line's description starts).
std::vector<std::string> wrap_help(const std::string& line, int width, size_t indent) {
  std::vector<std::string> out;
  std::string rest = line;
  while (int(rest.size()) > width && width > int(indent) + 10) {
    size_t cut = rest.rfind(' ', size_t(width));
    if (cut == std::string::npos || cut <= indent) cut = size_t(width);
    out.push_back(rest.substr(0, cut));
    const size_t next = rest.find_first_not_of(' ', cut);
    rest = std::string(indent, ' ') + (next == std::string::npos ? "" : rest.substr(next));
  }
  out.push_back(rest);
  return out;
}

}  // namespace

// Long lines wrap to the overlay's width, so it reads on 80 columns.
void App::draw_help(int rows, int cols) {
  const int w = std::min(cols - 2, 100);
  std::vector<std::pair<std::string, bool>> lines;  // text, bold
  for (const char* l : kHelp)
    for (const auto& piece : wrap_help(l, w - 2, 12)) lines.emplace_back(piece, false);
  lines.emplace_back("Commands (':' line and --script files):", true);
  for (const auto& l : script_help())
    for (const auto& piece : wrap_help("  " + l, w - 2, 30)) lines.emplace_back(piece, false);
  const int total = int(lines.size());
  int h = std::min(rows - 2, total);
  // Taller than the terminal: the last row says where the view is and how
  // to move it, so nothing is silently cut.
  const bool scrolls = h < total;
  const int body = scrolls ? h - 1 : h;
  help_top_ = std::max(0, std::min(help_top_, total - body));
  const int y0 = (rows - h) / 2, x0 = (cols - w) / 2;
  // Its rows blank across the whole width: the message and status rows it
  // covers show no letter either side of it.
  for (int r = 0; r < h; ++r) fill_row(y0 + r, 0, cols, 0);
  for (int r = 0; r < h; ++r) fill_row(y0 + r, x0, w, screen_.attr(Role::Selected));
  for (int i = 0; i < body; ++i) {
    const auto& [text, bold] = lines[size_t(help_top_ + i)];
    put(y0 + i, x0 + 1, text, w - 2, screen_.attr(Role::Selected) | (bold ? A_BOLD : 0));
  }
  if (scrolls)
    put(y0 + body, x0 + 1,
        fmt::format("-- lines {}-{} of {}: Up/Down, PgUp/PgDn scroll; any other key closes --", help_top_ + 1,
                    help_top_ + body, total),
        w - 2, screen_.attr(Role::Selected) | A_BOLD);
}

// The link's statistics, led by how the simulator ended while it is down:
// the link is not merely down, and R is the way back.
void App::draw_status(int y, int w) {
  const LinkStats st = console_.session().stats();
  if (!sim_down_.load()) {
    draw_status_bar(screen_, y, w, st, console_.session().port());
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
      paused_ ? std::vector<Sample>{} : console_.live().snapshot(size_t(std::min(1e9, view.window_steps + 2)));
  const std::vector<Sample>& samples = paused_ ? frozen_ : live;
  // The help covers the screen: nothing is drawn under it, so no plot dot
  // shows beside or through it (and no time goes into plots nobody sees).
  if (help_) {
    draw_message_line(rows - 3, cols);
    draw_status(rows - 2, cols);
    draw_key_bar(screen_, rows - 1, cols, sim_down_.load());
    draw_help(rows, cols);
    std::lock_guard<std::mutex> lock(ui_mu_);
    if (confirming_) draw_confirm(rows, cols);  // it takes the keys: it shows
    refresh();
    return;
  }
  if (path_view_) {
    // The newest 4096 samples make the shape; copying all that is kept
    // 25 times a second would cost 100 MB/s for nothing visible.
    draw_path_view(screen_, 1, 0, main_h, left_w, paused_ ? frozen_ : console_.live().snapshot(4096), ax_, ay_);
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
    if (confirming_) draw_confirm(rows, cols);
  }
  refresh();
}

int App::loop() {
  auto last_draw = Clock::now() - std::chrono::seconds(1);
  while (!quit_confirmed_) {
    {
      std::lock_guard<std::mutex> lock(ui_mu_);
      if (has_pending_prompt_ && !cmd_.active()) {
        has_pending_prompt_ = false;
        prompt_done_ = pending_prompt_.done;
        cmd_.start(pending_prompt_.label, pending_prompt_.initial);
      }
    }
    merge_older_samples();
    const int ch = getch();
    if (ch != ERR && !handle(ch)) break;
    // A firmware that reset behind a reconnect: old values must not stay on
    // screen as if they were in force.
    if (const uint32_t resets = console_.firmware_resets(); resets != seen_resets_) {
      seen_resets_ = resets;
      params_.reload_after_reset();
    }
    check_simulator();
    if (LiveConsole::interrupted()) break;  // SIGTERM, or Ctrl-C outside raw mode
    // Steady redraw whatever the telemetry or key rate: at most every 40 ms.
    if (Clock::now() - last_draw >= std::chrono::milliseconds(40)) {
      draw();
      last_draw = Clock::now();
    }
  }
  shutdown();
  return 0;
}

}  // namespace
}  // namespace tui

int run_tui(LiveConsole& console) {
  int rc = 0;
  {
    tui::Screen screen;
    tui::App app(console, screen);
    rc = app.loop();
  }
  console.set_notify({});
  // On the normal screen again (endwin): what stays after the TUI is gone.
  std::fputs(tui::exit_summary(console).c_str(), stdout);
  std::fflush(stdout);
  return rc;
}

}  // namespace nlsoft::console
