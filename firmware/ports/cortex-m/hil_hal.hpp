#pragma once
// Hardware in the loop: the link and the clock are the board's, the
// actuators and sensors are the simulated plant. The plant advances between
// control steps (advance(), called by the loop once per period), as a real
// plant moves while the MCU waits, so the compute time the firmware measures
// is the controller's alone, not the simulation's.
#include "firmware/core/hal.hpp"
#include "firmware/ports/cortex-m/board.hpp"

namespace nlsoft::fw::cortex_m {

template <class Plant>
class HilHal final : public Hal {
 public:
  static constexpr bool kMeasuresOutput = true;  // the simulated plant's true output
  explicit HilHal(float dt, uint32_t seed = 1) : dt_(dt), seed_(seed) {
    plant_.reset(seed);
    Plant::neutral_input(u_);
    sample();
  }

  size_t serial_read(uint8_t* buf, size_t cap) override { return board::serial_read(buf, cap); }
  size_t serial_write(const uint8_t* data, size_t len) override { return board::serial_write(data, len); }
  uint32_t ticks() override { return board::ticks(); }
  uint32_t tick_rate_hz() const override { return board::core_clock_hz(); }
  void actuate(const float* u, int m) override {
    for (int i = 0; i < m && i < Plant::m; ++i) u_[i] = u[i];
  }
  void read_sensors(float* l, int w) override {
    for (int i = 0; i < w && i < Plant::w; ++i) l[i] = l_[i];
  }
  bool read_output(float* y, int n) override {
    for (int j = 0; j < n && j < Plant::n; ++j) y[j] = y_[j];
    return true;
  }

  void start() {}
  // The plant's noise starts over from its seed at each run, as the
  // simulator's does (core/hal.hpp): otherwise a run's sensor noise depended
  // on how many periods the image idled before it, and the same ident
  // command recorded other data on each boot. The sensors are read again
  // from the new sequence: the run's first step reads them before the plant
  // advances.
  void run_begins() override {
    plant_.reseed_noise(seed_);
    sample();
  }

  // One period of the plant under the last command, then the sensors and
  // the true output the next step will read.
  void advance() {
    plant_.step(u_, dt_);
    sample();
  }

 private:
  void sample() {
    plant_.sensors(l_);
    plant_.output(y_);
  }

  Plant plant_;
  float dt_;
  uint32_t seed_;
  float u_[Plant::m] = {};
  float l_[Plant::w + 1] = {};  // +1: msd has no sensor channel
  float y_[Plant::n] = {};
};

}  // namespace nlsoft::fw::cortex_m
