#pragma once
// A Dynamixel servo as a device of the rig: checked at boot (PING, its
// model number, torque on), read between control steps like a sensor chip
// (present position, load, temperature: one READ and its status packet),
// and its health taken from every status packet's error byte. The goal
// positions are not written here but by write_goals(), one SYNC_WRITE per
// protocol for every servo of the bus at once, from the control step.
//
// Outcomes, as the sampler turns them into device states (PROTOCOL.md,
// DEVICE_STATUS): no answer at boot is kAbsent; an answer from another id,
// or another model number, kWrongId; a corrupt or missing answer once it
// had answered, kBusFault (stopped); a sound answer whose error byte is set
// (or, in 2.0, whose alert bit is: then the servo's Hardware Error Status
// says why), kFault, named by fault_names().
#include <cstddef>
#include <cstdint>

#include "firmware/drivers/bus.hpp"
#include "firmware/drivers/chip.hpp"
#include "firmware/drivers/dynamixel_packet.hpp"
#include "shared/chips/dynamixel.hpp"

namespace nlsoft::fw::drivers {

class DynamixelServo final : public Chip {
 public:
  struct Config {
    SerialBus* bus;
    uint8_t id;
    const chips::ChipSpec* spec;  // a servo's row (chips::on_serial)
  };
  explicit DynamixelServo(const Config& c) : c_(c) {}

  ChipStatus begin() override;
  // position (goal steps), load (the servo's raw item, signed), temperature (degC).
  ChipStatus read(float* out) override;
  int channels() const override { return 3; }
  size_t fault_names(const char** names, size_t max) const override;

  // Torque off (release) or on, by a WRITE the servo acknowledges.
  ChipStatus torque(bool on);
  uint8_t id() const { return c_.id; }
  // The status packet's error byte of the last answer (and, 2.0, the
  // Hardware Error Status behind its alert bit).
  uint8_t error() const { return error_; }
  uint8_t hardware_error() const { return hardware_error_; }

 private:
  static constexpr size_t kMaxParams = 24;  // the 2.0 present block, 21 bytes
  // One instruction and its status packet: kOk with the parameters in
  // params_/n_params_, or why not. `absent_if_silent`: at boot a silent bus
  // means no servo; later it means it stopped answering.
  // `answer_params`: the parameters the answer carries, so a 1.0 answer's
  // length is known and the bus stops listening once it came.
  ChipStatus transact(const uint8_t* packet, size_t n, size_t answer_params, bool absent_if_silent);
  ChipStatus read_item(uint16_t address, uint8_t length, bool absent_if_silent);
  ChipStatus judge_error();
  uint8_t protocol() const { return c_.spec->servo_protocol; }

  Config c_;
  uint8_t error_ = 0, hardware_error_ = 0;
  uint8_t params_[kMaxParams] = {};
  size_t n_params_ = 0;
};

// One servo's goal for write_goals(): its id, the protocol it speaks and
// its goal position in steps.
struct ServoGoal {
  uint8_t id;
  uint8_t protocol;
  uint32_t goal;
};

// Every servo's goal position in one SYNC_WRITE per protocol present (one
// on a bus of one kind), queued on `bus`; kBusError when a packet could not
// be encoded (more than `kMaxGoals` servos).
constexpr size_t kMaxGoals = 8;
BusStatus write_goals(SerialBus& bus, const ServoGoal* goals, size_t n);

}  // namespace nlsoft::fw::drivers
