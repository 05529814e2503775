// What the keys and the ':' line start on the worker: runs, holds,
// commands, and the simulator's restart.
#include <fmt/format.h>

#include "app/record/loop_rate.hpp"
#include "app/tui/app.hpp"

namespace nlsoft::console::tui {

void App::start_run() {
  worker_.post("starting a run", [this] {
    try {
      const int64_t id = console_.runs().start("");
      message(fmt::format("run {} started, recording to {}", id, console_.db_path()), Role::Ok);
    } catch (const std::exception& e) {
      message(e.what(), Role::Error);
    }
  });
}

void App::stop_run() {
  worker_.post("stopping the run", [this] {
    try {
      const RunSummary s = console_.runs().stop();
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

// F7: a firmware holding (or neutral) resumes, any other holds.
void App::hold(bool resume) {
  worker_.post("hold", [this, resume] {
    try {
      console_.runs().hold(resume ? protocol::HoldMode::Resume : protocol::HoldMode::Hold);
      message(resume ? "resumed" : "holding (F7 resumes)", Role::Ok);
    } catch (const std::exception& e) {
      message(e.what(), Role::Error);
    }
  });
}

void App::neutral() {
  worker_.post("neutral", [this] {
    try {
      console_.runs().hold(protocol::HoldMode::Neutral);
      message("actuators neutral (F7 resumes)", Role::Ok);
    } catch (const std::exception& e) {
      message(e.what(), Role::Error);
    }
  });
}

void App::save_settings() {
  worker_.post("saving settings", [this] {
    try {
      message(console_.device().settings(protocol::SettingsAction::Save), Role::Ok);
    } catch (const std::exception& e) {
      message(e.what(), Role::Error);
    }
  });
}

// Polled by the UI thread: a simulator that ended under the console (kill
// -9, a crash) is said once, with how; the run in progress is ended with
// that reason and its gap, and R offers a new simulator.
void App::check_simulator() {
  if (sim_down_.load()) return;
  const std::string gone = console_.simulator().exit_words();
  if (gone.empty()) return;
  sim_down_ = true;
  sim_gone_ = gone;
  message(gone + "; R restarts it", Role::Error);
  worker_.post("ending the run", [this, gone] {
    try {
      if (const auto s = console_.runs().end_simulator_gone())
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
    port = console_.simulator().respawn();
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

}  // namespace nlsoft::console::tui
