#pragma once
// What a recorded closed-loop run started with, read back to run it again:
// its rig, model, parameters and reference as they were at its first
// step, how many steps it lasted, and what of it a replay cannot repeat
// (parameters changed during it, frames it lost), in words.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "app/record/run_store.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

struct RecordedStart {
  RunRow row;
  std::vector<std::pair<std::string, std::string>> params;  // name, value text, as at its start
  RefParams reference{};
  uint32_t first_step = 0, last_step = 0;  // the firmware's step count, first and last sample
  bool on_simulator = true;                // recorded on nlsoft-firmware-sim (else a board or QEMU image)
  // The first sample's measured output and sensors (start_w of them; -1:
  // it holds no y_true): where a plant model starts a board's run.
  std::vector<float> start_y, start_l;
  int start_w = -1;
  // y then l: the channels a plant model starts from.
  std::vector<float> start_channels() const {
    std::vector<float> c = start_y;
    c.insert(c.end(), start_l.begin(), start_l.end());
    return c;
  }
  // What a replay does not repeat, each said before it runs: parameters
  // changed during the run (the replay keeps those it started with).
  std::vector<std::string> not_repeated;
};

// Throws CliError naming the run: no such run, no samples, an
// identification run (open loop: no controller to replay it through), a
// run of a board rather than the simulator unless `plant` (a plant model
// stands in for the rig: train --plant), a reference whose points the run
// does not keep.
RecordedStart recorded_start(RunStore& store, int64_t id, bool plant = false);

}  // namespace nlsoft::console
