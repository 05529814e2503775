#pragma once
// `runs replay N --controller pid`: what the rig's PID baseline ([pid] in
// its rig file, shared/pid.hpp) would have done on run N. The firmware runs
// no PID, so this is the offline loop `simulate --controller pid` runs
// (app/simulate/closed_loop.hpp) on the rig's simulated plant (or the
// source's plant model, started at run N's first sample): run N's
// reference and its input limits at its start, two seconds at rest first as
// the simulator idles before a run, the noise seed given, for as many steps
// as run N lasted. Recorded as a run of kind replay, without y_hat: a PID
// predicts nothing.
#include <cstdint>
#include <functional>
#include <string>

#include "app/record/recorder.hpp"
#include "app/replay/replay_source.hpp"

namespace nlsoft::console {

struct PidReplay {
  int64_t id = 0;        // the replay's run
  uint64_t samples = 0;  // one a step
  std::string gains;     // "kp 1.93, ki 4.01, kd 5.99, output scale 60", for its words
};

// Throws CliError: a rig without [pid] or a simulated plant, input limits
// the PID cannot clamp to.
PidReplay record_pid_replay(const ReplaySource& src, uint32_t seed, const std::string& label,
                            const std::string& notes, Recorder& recorder,
                            const std::function<void(long done, long total)>& progress = {});

}  // namespace nlsoft::console
