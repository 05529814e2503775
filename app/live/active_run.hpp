#pragma once
// The run in progress: its number, when it began, and the counters its
// samples keep. Several parts touch it from their own threads (the link's
// reader numbers samples, a run's thread starts, waits out and stops it,
// parameter and reference edits are logged into it), so it is one record
// with one owner (LiveConsole), handed to them by reference.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>

#include "app/record/recorder.hpp"

namespace nlsoft::console {

struct ActiveRun {
  explicit ActiveRun(Recorder& r) : recorder(r) {}

  // 0: none. Written by LiveRuns (start, stop), read by everyone.
  std::atomic<int64_t> id{0};
  // steady clock ns: a parameter edit on the UI thread reads it as a run starts.
  std::atomic<int64_t> started_ns{0};
  std::string label;  // LiveRuns' own, under its stop lock

  // Written by SampleIntake on the link's reader thread, reset by LiveRuns
  // before the run's id is published.
  std::atomic<uint64_t> k{0};     // samples numbered into the run
  std::atomic<uint64_t> lost{0};  // frames counted lost, as gaps
  std::atomic<bool> have_last_step{false};
  std::atomic<uint32_t> last_step{0}, first_step{0};
  std::atomic<int64_t> last_sample_ns{0};  // steady clock, when the run's last sample came
  std::atomic<bool> resync_after_gap{false};  // set by a link down: count the steps missed
  // A step count that went back (a reset firmware, a hostile one): the
  // run's steps no longer measure its progress, so it ends early rather
  // than read an unsigned difference that wrapped as "done".
  std::atomic<bool> step_went_back{false};
  std::atomic<uint32_t> step_back_from{0}, step_back_to{0};
  // STATUS: our run's state and watchdog bits, once it is no longer running.
  std::atomic<uint8_t> left_state{0}, left_watchdog{0};
  std::atomic<bool> user_hold{false};  // hold/neutral asked by us: telemetry pauses on purpose
  // A timed run's length in control steps (0: until stopped). Its samples
  // past it are not the run's: the firmware steps on until RUN_STOP
  // reaches it, a fast simulator thousands of steps, a different number
  // each time.
  std::atomic<uint64_t> planned_steps{0};

  // Both read by the reader thread and run_for while a stop writes them.
  std::atomic<uint16_t> decimation{1};            // the run's: telemetry's, or an identification run's
  std::atomic<uint16_t> telemetry_decimation{1};  // TELEMETRY_CONFIG's, put back when an identification run ends
  std::atomic<uint8_t> sensors_w{0};  // SENSOR_STREAM on: closed-loop samples carry these many sensors l (0: off)

  Recorder& recorder;

  std::chrono::steady_clock::time_point started() const {
    return std::chrono::steady_clock::time_point(std::chrono::steady_clock::duration(started_ns.load()));
  }
  // A parameter or reference sent during a run is part of what the run
  // measured: it goes into the run's parameter log with its time.
  void log_change(const std::string& name, const std::string& value) {
    if (const int64_t run = id.load()) {
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - started()).count();
      recorder.add_param_change(run, t, name, value);
    }
  }
};

}  // namespace nlsoft::console
