// The keys: the layers that take every key first (a yes/no box, the help,
// the ':' line, a panel's edit), then the key table's actions, then the
// panel with the focus.
#include <algorithm>

#include "app/tui/app.hpp"
#include "app/tui/curses.hpp"

namespace nlsoft::console::tui {

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
  if (const KeyBinding* b = key_binding(ch)) {
    const KeyResult r = on_key(b->action, ch);
    if (r != KeyResult::NotMine) return r == KeyResult::Done;
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

// Every action of the key table; a key that is not the console's here (Tab
// in the reference panel, R while the simulator runs) goes on to the panel.
App::KeyResult App::on_key(KeyAction action, int ch) {
  switch (action) {
    case KeyAction::None: return KeyResult::NotMine;
    case KeyAction::Restart:  // before the panels' own R (reread, rerun)
      if (!sim_down_.load()) return KeyResult::NotMine;
      restart_simulator();
      return KeyResult::Done;
    case KeyAction::Quit:
      if (console_.runs().running()) {
        confirm("a run is active: stop it and quit?",
                {console_.recording() ? "the run is stopped and kept in the database"
                                      : "the run is stopped; nothing is kept (--no-record)"},
                [this] { quit_confirmed_ = true; });
        return KeyResult::Done;
      }
      return KeyResult::Quit;
    case KeyAction::Help:
      help_ = true;
      help_top_ = 0;
      return KeyResult::Done;
    case KeyAction::FocusParams: focus(Focus::Params); return KeyResult::Done;
    case KeyAction::FocusRef: focus(Focus::Ref); return KeyResult::Done;
    case KeyAction::FocusRuns:
      focus(Focus::Runs);
      runs_.reload();
      return KeyResult::Done;
    case KeyAction::Messages:
      focus(Focus::Log);
      log_back_ = 0;
      return KeyResult::Done;
    case KeyAction::CycleFocus:
      if (ch == KEY_BTAB)
        focus(focus_ == Focus::Params ? Focus::Runs : focus_ == Focus::Ref ? Focus::Params : Focus::Ref);
      else if (focus_ != Focus::Ref)
        focus(focus_ == Focus::Params ? Focus::Ref : Focus::Params);
      else
        return KeyResult::NotMine;  // the reference panel's own Tab
      return KeyResult::Done;
    case KeyAction::Panel: panel_ = !panel_; return KeyResult::Done;
    case KeyAction::Start: start_run(); return KeyResult::Done;
    case KeyAction::Stop:
      // A timed run from the ':' line is ended where it waits; otherwise
      // the stop queues behind whatever the worker is doing.
      if (console_.runs().stop_timed()) message("stopping the timed run...");
      else stop_run();
      return KeyResult::Done;
    case KeyAction::Hold: {
      const uint8_t state = console_.session().stats().run_state;
      hold(state == uint8_t(protocol::RunState::Hold) || state == uint8_t(protocol::RunState::Neutral));
      return KeyResult::Done;
    }
    case KeyAction::Neutral: neutral(); return KeyResult::Done;
    case KeyAction::SaveSettings: save_settings(); return KeyResult::Done;
    case KeyAction::CommandLine:
      prompt_done_ = nullptr;
      cmd_.start(":");
      return KeyResult::Done;
    case KeyAction::PathView: path_view_ = !path_view_; return KeyResult::Done;
    case KeyAction::Tuning:
      if (tune_.empty()) message("no tuning session yet: :tune NAME=LO..HI[:log|:lin] ... (F1 for the options)", Role::Warn);
      else show_tune_ = !show_tune_;
      return KeyResult::Done;
    case KeyAction::PathAxes: {
      const int n = std::max(2, int(console_.device().info().n));
      ay_ = (ay_ + 1) % n;
      if (ay_ == ax_) ax_ = (ax_ + 1) % n, ay_ = (ax_ + 1) % n;
      return KeyResult::Done;
    }
    case KeyAction::ZoomIn: window_s_ = std::max(0.25, window_s_ / 2); return KeyResult::Done;
    case KeyAction::ZoomOut: window_s_ = std::min(120.0, window_s_ * 2); return KeyResult::Done;
    case KeyAction::PlotSignal:
      signal_ = next_plot_signal(signal_);
      path_view_ = false;
      return KeyResult::Done;
    case KeyAction::Pause: pause_plot(!paused_); return KeyResult::Done;
    case KeyAction::ScrollBack: scroll_plot(-0.5); return KeyResult::Done;
    case KeyAction::ScrollForward: scroll_plot(0.5); return KeyResult::Done;
    case KeyAction::CursorBack: move_cursor(-1); return KeyResult::Done;
    case KeyAction::CursorForward: move_cursor(1); return KeyResult::Done;
  }
  return KeyResult::NotMine;
}

}  // namespace nlsoft::console::tui
