#pragma once
// The liveness mark a recording console keeps on its run (recorder_pid,
// recorder_host, heartbeat_at in `runs`), and how another process tells a
// run being recorded from one a killed console left unfinished: deleting
// the first would pull the run from under its recorder, refusing the second
// forever would leave it undeletable.
#include <chrono>
#include <cstdint>
#include <string>

namespace nlsoft::console {

// The recorder renews heartbeat_at this often...
constexpr std::chrono::seconds kHeartbeatPeriod{1};
// ...so a mark this much older belongs to a console that is gone or frozen.
constexpr double kHeartbeatStaleS = 10;

std::string host_name();
double unix_now();  // seconds since 1970, the clock heartbeat_at is in

struct RecorderMark {
  int64_t pid = 0;  // 0: no mark (a run ended, or recorded before the mark existed)
  std::string host;
  double heartbeat_at = 0;
};

struct MarkVerdict {
  enum State { None, Live, Stale } state = None;
  std::string holder;  // "nlsoft-console (PID 4242)", with " on HOST" for another machine
  std::string why;     // for Stale: "PID 4242 is no longer running", "no heartbeat for 42 s"
};

// now: unix_now() of the caller.
MarkVerdict judge_mark(const RecorderMark& mark, double now);

}  // namespace nlsoft::console
