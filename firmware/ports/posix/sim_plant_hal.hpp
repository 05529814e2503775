#pragma once
// The simulated plant as a port's actuators, sensors and measured outputs:
// what the simulator runs in the loop. One class for the simulator's pty
// port (sim_hal.hpp) and the console's in-process replay of a run
// (app/replay/), so both step the very same plant code the same way.
#include "firmware/core/hal.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::fw::posix {

class SimPlantHal : public Hal {
 public:
  // Runs the hand-written plant `kind`; false (nothing changed) for one the
  // registry has not (shared/plant_registry.hpp).
  bool use_plant(PlantKind kind, uint32_t seed) {
    if (!plant_.select(kind, seed)) return false;
    seed_ = seed;
    dt_ = plant_.dt();
    return true;
  }
  // Runs a rig's generic plant; false (nothing changed) when the spec is
  // refused (generic_spec_problem).
  bool use_generic(const GenericPlantSpec& spec, uint32_t seed) {
    if (!plant_.select(spec, seed)) return false;
    seed_ = seed;
    dt_ = plant_.dt();
    return true;
  }
  void set_period(float dt) { dt_ = dt; }

  void actuate(const float* u, int) override { plant_.step(u, dt_); }
  void read_sensors(float* l, int) override { plant_.sensors(l); }
  bool read_output(float* y, int) override {
    plant_.output(y);
    return true;
  }
  // The noise starts over from the seed with every run: a run is the same
  // however long the simulator idled before it.
  void run_begins() override { plant_.reseed_noise(seed_); }

 private:
  SimPlant plant_;
  uint32_t seed_ = 0;
  float dt_ = 0.0f;
};

}  // namespace nlsoft::fw::posix
