#pragma once
// The interactive console's application: what it holds and the threads
// that touch it. Its methods are spread by concern: tui_app.cpp (its life:
// start, loop, shutdown), app_keys.cpp (the keys), app_draw.cpp (the
// screen), app_plot.cpp (the plot's view: pause, scroll, cursor, overlay),
// app_actions.cpp (what runs on the worker: runs, holds, commands, the
// simulator's restart).
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "app/live/live_console.hpp"
#include "app/record/run_store.hpp"
#include "app/script/script_runner.hpp"
#include "app/tui/key_table.hpp"
#include "app/tui/line_edit.hpp"
#include "app/tui/message_log.hpp"
#include "app/tui/param_panel.hpp"
#include "app/tui/plot_view.hpp"
#include "app/tui/ref_panel.hpp"
#include "app/tui/runs_panel.hpp"
#include "app/tui/screen.hpp"
#include "app/tui/tune_view.hpp"
#include "app/tui/ui.hpp"
#include "app/tui/worker.hpp"

namespace nlsoft::console::tui {

class App : public Ui {
 public:
  App(LiveConsole& console, Screen& screen);
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

  // What a key of the key table did: NotMine passes it on to the panel.
  enum class KeyResult { Done, Quit, NotMine };

  bool handle(int ch);  // false: quit
  KeyResult on_key(KeyAction action, int ch);
  void focus(Focus f);
  void draw();
  void draw_title(int w);
  void draw_message_line(int y, int w);
  void start_run();
  void stop_run();
  void hold(bool resume);
  void neutral();
  void save_settings();  // W: SETTINGS save
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
  uint32_t seen_resets_ = 0;  // console_.resets().count() the panel has caught up with
  // The simulator has ended and not been restarted yet (R): set by the UI
  // thread, cleared by the worker's restart.
  std::atomic<bool> sim_down_{false};
  std::string sim_gone_;  // how it ended (UI thread only)
};

}  // namespace nlsoft::console::tui
