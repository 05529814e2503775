#pragma once
// The simulator's firmware in this process: the firmware core with the
// simulator's plant in the loop (firmware/ports/posix/sim_plant_hal.hpp),
// set up as nlsoft-firmware-sim sets it up, talked to in frames as over its
// pty and stepped by the caller, one control period at a time. A run of the
// simulator is so replayed step for step, at no pace but the host's, and
// with nothing changed gives the very numbers the simulator gave.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/model/plant_model.hpp"
#include "host/rig/rig.hpp"
#include "protocol/encoder.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::console {

// A frame the firmware sent.
struct SimFrame {
  uint8_t type = 0, seq = 0;
  bool reply = false;
  std::vector<uint8_t> payload;
  template <class M>
  bool as(M& m) const {
    return type == uint8_t(M::kType) && protocol::unpack(payload.data(), payload.size(), m) == protocol::StatusCode::Ok;
  }
};

// A plant model in the simulated plant's place (a board's run replayed):
// held at `start` (its n + w channels: y then l, as the run's first sample)
// until a run begins, then stepped by the firmware's inputs from there, the
// inputs' history at the rig's neutral.
struct PlantStandIn {
  const model::PlantModel* model = nullptr;
  std::vector<float> start;
};

class SimulatorInProcess {
 public:
  // The rig's simulated plant with noise seed `seed` (or `plant`'s model
  // when given), at the rig's rate, running `model` (a model file's model
  // part). Throws CliError: a rig without a simulated plant and no plant
  // model, a model the firmware refuses.
  SimulatorInProcess(const host::Rig& rig, const std::vector<uint8_t>& model, uint32_t seed,
                     const PlantStandIn& plant = {});
  ~SimulatorInProcess();
  SimulatorInProcess(const SimulatorInProcess&) = delete;
  SimulatorInProcess& operator=(const SimulatorInProcess&) = delete;

  // One request, and the reply with its seq (frames sent meanwhile are
  // kept for take_frames). Throws CliError when none comes: the firmware
  // answers every request at once, so none is an internal fault.
  template <class M>
  SimFrame request(const M& m) {
    uint8_t wire[protocol::kWireBufferSize];
    const uint8_t seq = seq_++;
    const size_t len = protocol::encode(m, seq, 0, wire, sizeof wire);
    return exchange(wire, len, seq, protocol::message_name(uint8_t(M::kType)));
  }

  // One control period: the clock moves on by it, the port is served, the
  // firmware steps (the plant with it).
  void step();
  // The frames sent since the last call that were not a request's reply.
  std::vector<SimFrame> take_frames();
  double rate_hz() const { return rate_hz_; }

 private:
  struct Impl;
  SimFrame exchange(const uint8_t* wire, size_t len, uint8_t seq, const char* what);
  std::unique_ptr<Impl> impl_;
  uint8_t seq_ = 1;
  double rate_hz_ = 0;
};

}  // namespace nlsoft::console
