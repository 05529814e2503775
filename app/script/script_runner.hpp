#pragma once
// Executes parsed script commands against a connected console. The same
// runner serves `--script FILE` (exit codes for CI) and the TUI's `:` line.
#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "app/live/live_console.hpp"
#include "app/script/script_parser.hpp"
#include "app/tune/tuner.hpp"

namespace nlsoft::console {

class ScriptRunner {
 public:
  using Output = std::function<void(const std::string& line)>;
  using Progress = std::function<void(const std::string& what, size_t done, size_t total)>;

  ScriptRunner(LiveConsole& console, Output out, Progress progress = {})
      : console_(console), out_(std::move(out)), progress_(std::move(progress)) {}

  // Told of each evaluation of a `tune` (the TUI's convergence view). Set
  // before commands run; called on the thread that executes them.
  void set_tune_observer(std::function<void(const TuneEvaluation&)> f) { tune_observer_ = std::move(f); }

  // Runs every command in order. Returns 0 when every expect held, every
  // timed run completed and every tune found a set, 1 when one did not, 2 on a script, link or
  // recording error (the message names file:line; an active run is stopped
  // first).
  int run(const Script& script);

  // One command; throws ScriptError (file:line: ...) on failure. A failed
  // expect, or a run that ended early, is not an exception: it is reported
  // and counted.
  void execute(const Command& c, const std::string& file);

  // From another thread: the command in progress ends as soon as it can
  // (a run is stopped and kept, a wait or sweep returns) and this and every
  // later command throws ScriptError "cancelled". Sticky: the TUI calls it
  // once, at quit, before joining the thread that executes commands.
  void cancel();
  bool cancelled() const { return cancelled_.load(); }

  int failed_expects() const { return failed_; }
  int passed_expects() const { return passed_; }
  int incomplete_runs() const { return incomplete_runs_; }  // ended early without early=ok
  int fruitless_tunes() const { return fruitless_tunes_; }  // tune sessions where every evaluation failed

 private:
  void say_changes(const std::vector<std::string>& lines, const std::string& none);
  void ref_load(const Command& c);
  void model_upload(const Command& c);
  void timed_run(const Command& c, const std::string& file);
  void ident(const Command& c, const std::string& file);
  void wait(double seconds);
  void expect(const Command& c, const std::string& file);
  void note(const std::string& text);
  void sweep(const Command& c, const std::string& file);
  void tune(const Command& c);
  TuneResult tune_on_replays(TuneOptions& o, const TuneCallbacks& cb);
  void check_completed(const RunSummary& s, const Command& c, const std::string& file);
  void merge_capture(int64_t run_id, const Command& c);
  void throw_if_cancelled(const Command& c, const std::string& file) const;
  LiveConsole& console_;
  Output out_;
  Progress progress_;
  std::function<void(const TuneEvaluation&)> tune_observer_;
  int failed_ = 0, passed_ = 0, incomplete_runs_ = 0, fruitless_tunes_ = 0;
  std::atomic<bool> cancelled_{false};
  std::mutex cancel_mu_;  // with cancel_cv_: a `wait` ends at cancel()
  std::condition_variable cancel_cv_;
};

}  // namespace nlsoft::console
