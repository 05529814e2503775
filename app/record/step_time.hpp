#pragma once
// A sample's time on the control loop's own clock: its step count from the
// run's first step over the run's nominal loop rate. That is what a model's
// sample time is, on a board and on a simulator alike; the firmware's
// time_us is not, for a --sim-fast simulator steps as fast as the host runs
// and its time_us is the host's clock (34 us per step of an 80 Hz rig).
// `runs merge-y` times a run the same way (app/record/merge_y.cpp).
#include <cstdint>
#include <limits>

namespace nlsoft::console {

class StepClock {
 public:
  explicit StepClock(double loop_rate_hz) : rate_hz_(loop_rate_hz) {}

  // Seconds since the run's first sample that carried a step; NaN for a
  // sample without one, or for a run that recorded no loop rate. The step
  // counter is 32-bit: a difference taken modulo 2^32 goes on across a wrap.
  double at(bool has_step, uint32_t step) {
    if (!has_step || !(rate_hz_ > 0)) return std::numeric_limits<double>::quiet_NaN();
    if (!started_) step0_ = step, started_ = true;
    return double(uint32_t(step - step0_)) / rate_hz_;
  }

 private:
  double rate_hz_;
  uint32_t step0_ = 0;
  bool started_ = false;
};

}  // namespace nlsoft::console
