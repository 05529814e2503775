#pragma once
// The run's lifecycle: started (closed loop or identification), held,
// waited out for a duration with every way it can end early, stopped once
// whoever stops it, and its summary. Separate because several threads end
// a run (a timed run's own, the TUI's keys and quit, the console's
// shutdown, a simulator that died) and it must close exactly once.
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "app/link/device.hpp"
#include "app/live/active_run.hpp"
#include "app/live/live_buffer.hpp"
#include "app/live/live_options.hpp"
#include "app/live/live_references.hpp"
#include "app/live/notices.hpp"
#include "app/live/simulator_child.hpp"
#include "app/record/run_metrics.hpp"

namespace nlsoft::console {

struct RunSummary {
  int64_t run_id = 0;
  std::string label, end_reason;
  // A timed run that stopped before its duration for a reason nobody asked
  // for: telemetry stopped (firmware died, link gone), the firmware left the
  // run (its link watchdog tripped). Scripts fail on it unless told not to.
  bool ended_early = false;
  RunMetrics metrics;
};

class LiveRuns {
 public:
  using Progress = std::function<void(size_t done, size_t total)>;
  // What a run needs of the connection; all of it outlives the runs
  // (LiveConsole owns it).
  struct Parts {
    Device& device;
    Session& session;
    ActiveRun& run;
    LiveBuffer& live;  // cleared as a run starts
    LiveReferences& references;
    SimulatorChild& simulator;
    Notices& notices;
    const LiveOptions& options;
    const std::string& db_path;
  };
  explicit LiveRuns(Parts parts) : p_(parts) {}

  // start records the run (when recording) and sends RUN_START; stop sends
  // RUN_STOP and closes the run with its metrics.
  int64_t start(const std::string& label);
  RunSummary stop(const std::string& reason = "stopped");
  void hold(protocol::HoldMode mode);
  bool running() const { return p_.run.id.load() != 0; }
  int64_t current() const { return p_.run.id.load(); }
  uint64_t samples() const { return p_.run.k.load(); }
  // Blocks until `seconds` of control steps have been recorded (by the
  // firmware's step count, so a faster-than-real-time simulator finishes
  // early), then stops the run. Ends early, stopping the run, when *cancel
  // becomes true or stop_timed() is called; returns at once, with that
  // stop's summary, when another thread stops the run (stop, or the
  // console shutting down). Ends early with ended_early set, recording the
  // missing steps as a gap with its duration, when no telemetry comes for
  // the silence limit (or a user hold) or STATUS says the firmware left the
  // run. Throws CliError, after closing the run, if recording fails (disk
  // full): a run nobody can read back is not worth waiting out.
  RunSummary run_for(double seconds, const std::string& label, const Progress& progress = {},
                     const std::atomic<bool>* cancel = nullptr);
  // An identification run (protocol 1.3, IDENT_START): the firmware drives
  // the inputs with its excitation signal for start.duration steps and ends
  // the run itself; recorded as an identification run (kind 'ident', the
  // signal as `excitation` JSON, u, measured y and the sensors per sample).
  // start.run_id is set here. Ends as run_for does (early, interrupted).
  // Throws CliError when the firmware has no IDENT capability or refuses.
  RunSummary run_ident(protocol::IdentStart start, const std::string& excitation_json, const std::string& label,
                       const Progress& progress = {});
  // Ends a run_for() early from another thread (the TUI's stop key while a
  // `run 10s` from the command line is going). Returns false if none is.
  bool stop_timed() {
    if (!timed_run_.load()) return false;
    stop_timed_ = true;
    return true;
  }
  // Once the simulator has ended: ends the run in progress (not a timed
  // one, which ends itself) with its words as the reason and the time
  // since its last sample as a gap. Returns its summary, if there was one.
  std::optional<RunSummary> end_simulator_gone();

  std::optional<RunSummary> last() const;
  // Every run this console started, in order (the TUI names them at exit).
  std::vector<int64_t> session_runs() const;
  RunMetrics metrics(int64_t run_id, double skip_s = 0, double window_s = 0);

 private:
  // stop's body; the caller holds stop_mu_ and id is the active run.
  RunSummary stop_locked(int64_t id, const std::string& reason);
  // Stops run `id` if it is still the active one, else returns the summary
  // of whoever stopped it.
  RunSummary finish(int64_t id, const std::string& label, const std::string& reason);
  // start's body; an identification run when ident is given.
  // planned_steps: a timed run's length (ActiveRun::planned_steps), 0 for one run until stopped.
  int64_t begin(const std::string& label, protocol::IdentStart* ident, const std::string& excitation_json,
                uint64_t planned_steps);
  // run_for's body over a number of control steps.
  RunSummary run_steps(uint64_t target, int64_t id, const std::string& label, const Progress& progress,
                       const std::atomic<bool>* cancel);
  // How run_steps' wait for its steps ended.
  struct TimedEnd {
    enum Kind { Reached, Stopped, Cancelled, Interrupted, StoppedElsewhere, RecordFailed, Early } kind;
    std::string words;  // RecordFailed: the database's error; Early: why the run ended
  };
  TimedEnd wait_for_steps(uint64_t target, int64_t id, const Progress& progress, const std::atomic<bool>* cancel,
                          std::chrono::steady_clock::time_point started);
  void record_early_end_gap(int64_t id, uint64_t target, std::chrono::steady_clock::time_point started,
                            const std::string& early);
  [[noreturn]] void fail_recording(int64_t id, const std::string& label, const std::string& error);
  double loop_rate_hz() const;  // the firmware's, or 100 Hz when it names none

  Parts p_;
  // Held across a whole stop, so two threads stopping the same run (the
  // TUI quitting while a worker's run_for ends it) close it once, and a
  // run_for that saw its run stopped can wait for that stop's summary.
  std::mutex stop_mu_;
  mutable std::mutex mu_;
  std::optional<RunSummary> last_run_;
  std::vector<int64_t> session_runs_;
  std::atomic<bool> timed_run_{false}, stop_timed_{false};
};

}  // namespace nlsoft::console
