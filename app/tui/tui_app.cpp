#include "app/tui/tui_app.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>

#include "app/tui/app.hpp"
#include "app/live/interrupt.hpp"
#include "app/tui/completion.hpp"
#include "app/tui/exit_summary.hpp"
#include "app/tui/curses.hpp"

namespace nlsoft::console {

namespace tui {

App::App(LiveConsole& console, Screen& screen)
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
  console_.notices().listen([this](const std::string& s) { message(s, Role::Warn); });
  params_.reload();
  runs_.reload();
  if (const UdpStream* u = console_.udp())
    message(fmt::format("streaming every telemetry sample to {} (UDP, JSON)", u->target()), Role::Ok);
  const auto info = console_.device().info();
  message(fmt::format("connected to {} {}.{}.{}: F5 starts a run, F1 help", info.firmware, info.fw_major,
                      info.fw_minor, info.fw_patch),
          Role::Ok);
}

// The shutdown order, on quit (q, F10, SIGTERM) and in ~App if loop() threw:
//  1. cancel the `:` command in progress: a timed run is stopped and kept, a
//     wait, sweep or tune returns (ScriptRunner::cancel; a tune still puts
//     the parameters back and saves its best, bounded by the link's timeouts);
//  2. stop and join the worker: the task running finishes (bounded by the
//     link's timeouts), queued ones are dropped; afterwards no other thread
//     touches the panels, the runner or the message log;
//  3. detach the console's notices listener: Notices::say calls it under
//     its mutex, so once listen({}) returns the link's threads are done with
//     message();
//  4. stop a run still active (F5) on this thread, so it is kept with an end;
// then the members are destroyed, in any order.
void App::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  runner_.cancel();
  worker_.stop();
  console_.notices().listen({});
  if (console_.runs().running()) {
    try {
      console_.runs().stop(interrupted() ? interrupt_reason() : "stopped at quit");
    } catch (...) {
      // Quitting regardless; the run stays open in the database (ended_at NULL).
    }
  }
}

// A panel given the keys is shown; the reference panel opens on the
// reference in force, not on whatever it showed last.
void App::focus(Focus f) {
  if (f == Focus::Ref && (focus_ != Focus::Ref || !panel_)) refs_.show_in_force();
  focus_ = f;
  panel_ = true;
}

int App::loop() {
  using Clock = std::chrono::steady_clock;
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
    if (const uint32_t resets = console_.resets().count(); resets != seen_resets_) {
      seen_resets_ = resets;
      params_.reload_after_reset();
    }
    check_simulator();
    if (interrupted()) break;  // SIGTERM, or Ctrl-C outside raw mode
    // Steady redraw whatever the telemetry or key rate: at most every 40 ms.
    if (Clock::now() - last_draw >= std::chrono::milliseconds(40)) {
      draw();
      last_draw = Clock::now();
    }
  }
  shutdown();
  return 0;
}

}  // namespace tui

int run_tui(LiveConsole& console) {
  int rc = 0;
  {
    tui::Screen screen;
    tui::App app(console, screen);
    rc = app.loop();
  }
  console.notices().listen({});
  // On the normal screen again (endwin): what stays after the TUI is gone.
  std::fputs(tui::exit_summary(console).c_str(), stdout);
  std::fflush(stdout);
  return rc;
}

}  // namespace nlsoft::console
