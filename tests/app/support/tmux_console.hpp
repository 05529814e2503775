#pragma once
// The console as a person drives it: nlsoft-console in tmux, keys sent with
// send-keys, the screen read back with capture-pane. Shared by the TUI tests.
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/text_checks.hpp"
#include "run_process.hpp"

namespace nlsoft::console::tui_test {

using test::run_process;
using test::shell_quote;

inline bool have_tmux() { return run_process("command -v tmux").code == 0; }

class Tmux {
 public:
  Tmux(const std::string& command, const std::string& env, int cols = 120, int rows = 40)
      // A server of its own per session: the last test's, just told to
      // exit, may still hold a shared socket ("server exited unexpectedly").
      : socket_("nlsoft-tui-test-" + std::to_string(::getpid()) + "-" + std::to_string(++sessions_)) {
    const auto r = run_process(tmux() + " new-session -d -s ui -x " + std::to_string(cols) + " -y " +
                               std::to_string(rows) + " " + shell_quote("env " + env + " " + command));
    started_ = r.code == 0;
    if (!started_) error_ = r.output;
  }
  ~Tmux() { run_process(tmux() + " kill-server"); }
  bool started() const { return started_; }
  const std::string& error() const { return error_; }

  std::string screen() const { return run_process(tmux() + " capture-pane -p -t ui").output; }
  // With the attributes as escape sequences (reverse video: ESC [7m).
  std::string screen_with_attributes() const { return run_process(tmux() + " capture-pane -e -p -t ui").output; }
  void keys(const std::string& keys) const { run_process(tmux() + " send-keys -t ui " + keys); }
  void resize(int cols, int rows) const {
    run_process(tmux() + " resize-window -t ui -x " + std::to_string(cols) + " -y " + std::to_string(rows));
  }
  bool alive() const { return run_process(tmux() + " has-session -t ui").code == 0; }
  // The process the pane runs (what `tmux display -p '#{pane_pid}'` says).
  pid_t pane_pid() const { return pid_t(std::atoi(run_process(tmux() + " display -p -t ui '#{pane_pid}'").output.c_str())); }

  // Polls the screen until pred holds (the UI redraws at 25 Hz); returns the
  // last screen either way so a failure shows what was drawn.
  bool wait_for(const std::function<bool(const std::string&)>& pred, std::string& last, int seconds = 15) const {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    while (std::chrono::steady_clock::now() < end) {
      last = screen();
      if (pred(last)) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }
  // Connected and the parameter list read: the panel shows its last row.
  bool wait_until_connected(std::string& last) const;

 private:
  std::string tmux() const { return "tmux -L " + socket_; }
  static inline int sessions_ = 0;
  std::string socket_;
  bool started_ = false;
  std::string error_;
};

using nlsoft::test::contains;

// The frame is painted down to its last row, the key bar: curses writes a
// frame top to bottom, and under load tmux may show one half written (the
// panel read, the rows below it still blank).
inline bool key_bar_drawn(const std::string& x) { return contains(x, "qQuit"); }

inline bool Tmux::wait_until_connected(std::string& last) const {
  // Below 100 columns the panel abbreviates the longer names.
  return wait_for([](const std::string& x) {
    return contains(x, "Parameters (") && (contains(x, "safe_state") || contains(x, "safe_s\u2026")) &&
           key_bar_drawn(x);
  }, last);
}

// The line of the screen that holds `what` ("" if none).
inline std::string line_with(const std::string& screen, const std::string& what) {
  const size_t at = screen.find(what);
  if (at == std::string::npos) return "";
  const size_t start = screen.rfind('\n', at);
  const size_t b = start == std::string::npos ? 0 : start + 1;
  return screen.substr(b, screen.find('\n', at) - b);
}

// A row of the parameter panel: the name is printed padded to 12 columns.
inline std::string param_row(const std::string& screen, const std::string& name) {
  std::string padded = name;
  padded.resize(12, ' ');
  const size_t at = screen.find(" " + padded);
  if (at == std::string::npos) return "";
  return screen.substr(at, screen.find('\n', at) - at);
}

inline std::vector<std::string> screen_lines(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

inline std::string quit_status(const std::string& screen) {
  const size_t at = screen.find("EXIT=");
  return at == std::string::npos ? "" : screen.substr(at, screen.find('\n', at) - at);
}

inline const char* const kUtf8Env = "LANG=C.UTF-8 LC_ALL=C.UTF-8 NLSOFT_FIRMWARE_SIM=" NLSOFT_FIRMWARE_SIM_BIN;

// A console in tmux at cols x rows whose exit status shows on the pane.
inline Tmux console_in(const std::string& args, int cols, int rows) {
  return Tmux("sh -c " + shell_quote(std::string(NLSOFT_CONSOLE_BIN) + " " + args + "; echo EXIT=$?; sleep 30"),
              kUtf8Env, cols, rows);
}

inline bool panel_read(const std::string& x) {
  return contains(x, "Parameters (") && contains(x, "Lambda") && key_bar_drawn(x);
}

}  // namespace nlsoft::console::tui_test
