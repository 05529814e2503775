// The Dynamixel servo driver against a fake chain of servos (the same fake
// the QEMU test puts on the board's USART): boot checks, reads, one
// SYNC_WRITE of the goals, and every way a servo fails, each reported as
// the device state and the reason the console logs.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "firmware/core/sensor_sampler.hpp"
#include "firmware/drivers/dynamixel_servo.hpp"
#include "shared/chips/catalog.hpp"
#include "tests/firmware/servos/fake_servo_chain.hpp"

namespace nlsoft::fw::drivers {
namespace {

using test::FakeServoChain;
using test::ServoFault;

// The bus as a test sees it: what the master sends goes to the fake chain,
// whose answers come back on the next exchange. No echo (the port's
// receiver is off while it sends).
class ChainBus final : public SerialBus {
 public:
  explicit ChainBus(FakeServoChain& chain) : chain_(chain) {}
  BusStatus exchange(const uint8_t* tx, size_t n, uint8_t* rx, size_t cap, size_t& got) override {
    if (n > 0) chain_.receive(tx, n, line_);
    if (drop_next) {
      line_.clear();
      drop_next = false;
    }
    got = line_.size() < cap ? line_.size() : cap;
    for (size_t i = 0; i < got; ++i) rx[i] = line_[i];
    line_.erase(line_.begin(), line_.begin() + long(got));
    ++exchanges;
    return got == 0 ? BusStatus::kTimeout : BusStatus::kOk;
  }
  // An answer still on its way when the master gave up (a late servo):
  // it arrives at the start of the next exchange.
  void late(const std::vector<uint8_t>& bytes) { line_.insert(line_.begin(), bytes.begin(), bytes.end()); }
  BusStatus send(const uint8_t* tx, size_t n) override {
    std::vector<uint8_t> answer;
    chain_.receive(tx, n, answer);
    sent.insert(sent.end(), tx, tx + n);
    unanswered += answer.size();
    return BusStatus::kOk;
  }
  int exchanges = 0;
  size_t unanswered = 0;
  bool drop_next = false;  // the next answer lost on the line
  std::vector<uint8_t> sent;

 private:
  FakeServoChain& chain_;
  std::vector<uint8_t> line_;  // answers not yet taken
};

struct Rig {
  FakeServoChain chain;
  ChainBus bus{chain};
  Rig() {
    chain.servos.emplace_back(1, 1, 64);    // RX-64
    chain.servos.emplace_back(2, 1, 64);
    chain.servos.emplace_back(7, 2, 1020);  // XM430-W350
  }
};

std::vector<std::string> names_of(const Chip& c) {
  const char* n[8];
  const size_t k = c.fault_names(n, 8);
  return std::vector<std::string>(n, n + k);
}

TEST(DynamixelServo, BootsTurnsTorqueOnAndReadsPositionLoadTemperature) {
  Rig r;
  DynamixelServo rx({&r.bus, 1, &chips::kRx64});
  ASSERT_EQ(rx.begin(), ChipStatus::kOk);
  EXPECT_EQ(r.chain.find(1)->table[24], 1) << "torque enable";
  r.chain.find(1)->put(36, 2, 700);
  r.chain.find(1)->put(40, 2, 0x400 | 123);  // 123 clockwise
  r.chain.find(1)->put(43, 1, 41);
  float v[3] = {};
  ASSERT_EQ(rx.read(v), ChipStatus::kOk);
  EXPECT_EQ(v[0], 700.0f);
  EXPECT_EQ(v[1], -123.0f);
  EXPECT_EQ(v[2], 41.0f);

  DynamixelServo xm({&r.bus, 7, &chips::kXm430W350});
  ASSERT_EQ(xm.begin(), ChipStatus::kOk);
  EXPECT_EQ(r.chain.find(7)->table[64], 1) << "torque enable (2.0)";
  r.chain.find(7)->put(132, 4, 3000);
  r.chain.find(7)->put(126, 2, uint16_t(-250));
  ASSERT_EQ(xm.read(v), ChipStatus::kOk);
  EXPECT_EQ(v[0], 3000.0f);
  EXPECT_EQ(v[1], -250.0f);
  EXPECT_EQ(v[2], 36.0f);
  EXPECT_EQ(r.chain.bad_packets, 0u);
}

TEST(DynamixelServo, OneSyncWritePerProtocolCarriesEveryGoalAndNobodyAnswers) {
  Rig r;
  std::vector<std::pair<int, uint32_t>> seen;
  r.chain.on_goal = [&](uint8_t id, uint32_t goal) { seen.emplace_back(id, goal); };
  const ServoGoal goals[] = {{1, 1, 277}, {2, 1, 747}, {7, 2, 4000}};
  ASSERT_EQ(write_goals(r.bus, goals, 3), BusStatus::kOk);
  EXPECT_EQ(r.chain.packets, 2u) << "one SYNC_WRITE per protocol";
  EXPECT_EQ(r.bus.unanswered, 0u);
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0], std::make_pair(1, 277u));
  EXPECT_EQ(seen[1], std::make_pair(2, 747u));
  EXPECT_EQ(seen[2], std::make_pair(7, 4000u));
  // Protocol 1.0's SYNC_WRITE of two 2-byte goals is 14 bytes (the rig file's bus budget), then 2.0's.
  ASSERT_GT(r.bus.sent.size(), 14u);
  EXPECT_EQ(r.bus.sent[3], 14 - 4) << "LEN";
  EXPECT_EQ(r.bus.sent[4], 0x83);
  EXPECT_EQ(r.bus.sent[14], 0xFF);
  EXPECT_EQ(r.bus.sent[16], 0xFD) << "the 2.0 packet starts right after the 1.0 one";
  ServoGoal too_many[kMaxGoals + 1] = {};
  EXPECT_EQ(write_goals(r.bus, too_many, kMaxGoals + 1), BusStatus::kBusError);
}

TEST(DynamixelServo, EachFailureIsItsOwnState) {
  {  // nothing answers at boot: absent; after it answered once: a read that gets silence is a stopped bus
    Rig r;
    DynamixelServo s({&r.bus, 3, &chips::kRx64});
    EXPECT_EQ(s.begin(), ChipStatus::kAbsent);
    DynamixelServo one({&r.bus, 1, &chips::kRx64});
    ASSERT_EQ(one.begin(), ChipStatus::kOk);
    r.chain.find(1)->fault = ServoFault::kSilent;
    float v[3];
    EXPECT_EQ(one.read(v), ChipStatus::kBusFault);
  }
  {  // an answer from another id
    Rig r;
    r.chain.find(2)->fault = ServoFault::kWrongId;
    DynamixelServo s({&r.bus, 2, &chips::kRx64});
    EXPECT_EQ(s.begin(), ChipStatus::kWrongId);
  }
  {  // another model at that id
    Rig r;
    DynamixelServo s({&r.bus, 1, &chips::kMx28});
    EXPECT_EQ(s.begin(), ChipStatus::kWrongId);
  }
  {  // a corrupt checksum
    Rig r;
    DynamixelServo s({&r.bus, 1, &chips::kRx64});
    ASSERT_EQ(s.begin(), ChipStatus::kOk);
    r.chain.find(1)->fault = ServoFault::kCorrupt;
    float v[3];
    EXPECT_EQ(s.read(v), ChipStatus::kBusFault);
  }
}

TEST(DynamixelServo, AnErrorByteIsAFaultNamedAsTheManualNamesIt) {
  Rig r;
  DynamixelServo rx({&r.bus, 2, &chips::kRx64});
  ASSERT_EQ(rx.begin(), ChipStatus::kOk);
  r.chain.find(2)->fault = ServoFault::kError;
  r.chain.find(2)->error = dynamixel::p1::kOverload | dynamixel::p1::kOverheating;
  float v[3] = {9, 9, 9};
  EXPECT_EQ(rx.read(v), ChipStatus::kFault);
  EXPECT_EQ(v[0], 9.0f) << "a fault leaves the reading untouched";
  EXPECT_EQ(names_of(rx), (std::vector<std::string>{"overheating", "overload"}));
  // At boot too: a servo in error is a fault, its torque left alone.
  DynamixelServo again({&r.bus, 2, &chips::kRx64});
  r.chain.find(2)->table[24] = 0;
  EXPECT_EQ(again.begin(), ChipStatus::kFault);
  EXPECT_EQ(r.chain.find(2)->table[24], 0);

  // 2.0: the alert bit sends the driver to the Hardware Error Status.
  DynamixelServo xm({&r.bus, 7, &chips::kXm430W350});
  ASSERT_EQ(xm.begin(), ChipStatus::kOk);
  r.chain.find(7)->fault = ServoFault::kError;
  r.chain.find(7)->error = dynamixel::p2::kAlert;
  r.chain.find(7)->hardware_error = 0x20 | 0x01;  // overload, input voltage
  EXPECT_EQ(xm.read(v), ChipStatus::kFault);
  EXPECT_EQ(names_of(xm), (std::vector<std::string>{"input voltage", "overload"}));
  r.chain.find(7)->error = 4;  // data range, no alert
  EXPECT_EQ(xm.read(v), ChipStatus::kFault);
  EXPECT_EQ(names_of(xm), (std::vector<std::string>{"data range"}));
  // Healthy again: ok, and the reading comes through.
  r.chain.find(7)->fault = ServoFault::kNone;
  EXPECT_EQ(xm.read(v), ChipStatus::kOk);
}

// A late answer (to a PING the master gave up on) ahead of the one it
// waits for: skipped, and the right one still taken, so the answers do not
// shift one instruction along for good.
TEST(DynamixelServo, ALateAnswerAheadOfTheRightOneIsSkipped) {
  Rig r;
  DynamixelServo s1({&r.bus, 1, &chips::kRx64});
  ASSERT_EQ(s1.begin(), ChipStatus::kOk);
  uint8_t stale[16];
  const dynamixel::Encoded e = dynamixel::p1::status(2, 0, nullptr, 0, stale, sizeof stale);
  ASSERT_TRUE(e.ok());
  r.bus.late(std::vector<uint8_t>(stale, stale + e.length));
  r.chain.find(1)->put(36, 2, 321);
  float v[3] = {};
  EXPECT_EQ(s1.read(v), ChipStatus::kOk);
  EXPECT_EQ(v[0], 321.0f);
  // Nothing left on the line for the next one.
  EXPECT_EQ(s1.read(v), ChipStatus::kOk);
}

TEST(DynamixelServo, OneLostAnswerIsAskedAgainNotAStoppedServo) {
  Rig r;
  DynamixelServo s1({&r.bus, 1, &chips::kRx64});
  ASSERT_EQ(s1.begin(), ChipStatus::kOk);
  r.chain.find(1)->put(36, 2, 654);
  r.bus.drop_next = true;
  float v[3] = {};
  EXPECT_EQ(s1.read(v), ChipStatus::kOk);
  EXPECT_EQ(v[0], 654.0f);
}

TEST(DynamixelServo, TorqueOffIsAWriteTheServoTakes) {
  Rig r;
  DynamixelServo rx({&r.bus, 1, &chips::kRx64});
  ASSERT_EQ(rx.begin(), ChipStatus::kOk);
  EXPECT_EQ(rx.torque(false), ChipStatus::kOk);
  EXPECT_EQ(r.chain.find(1)->table[24], 0);
  DynamixelServo none({nullptr, 1, &chips::kRx64});
  EXPECT_EQ(none.begin(), ChipStatus::kBadConfig);
  DynamixelServo not_a_servo({&r.bus, 1, &chips::kLis3mdl});
  EXPECT_EQ(not_a_servo.begin(), ChipStatus::kBadConfig);
}

// Through the sampler, as the firmware holds devices: a fault is the
// device state `fault`, and its names reach the caller for the LOG.
TEST(DynamixelServo, TheSamplerReportsAFaultAndItsReasons) {
  Rig r;
  DynamixelServo s1({&r.bus, 1, &chips::kRx64});
  DynamixelServo s2({&r.bus, 2, &chips::kRx64});
  Chip* chips[] = {&s1, &s2};
  const RigDeviceConfig devices[] = {
      {"rx64-1", &chips::kRx64, 3, BusKind::Serial, 1, 0, 1000000u, {0.0f, 0}, {25.0f, 1}, false},
      {"rx64-2", &chips::kRx64, 3, BusKind::Serial, 2, 0, 1000000u, {0.0f, 0}, {25.0f, 1}, true},
  };
  SensorSampler::Slot slots[2];
  const RigSensorSource sources[] = {{SensorFrom::Device, 1, 0, 1.0f, 0.0f}};
  SensorSampler sampler(chips, devices, slots, 2, sources, 1);
  sampler.begin(0);
  EXPECT_EQ(sampler.state(0), DeviceState::Ok);
  EXPECT_EQ(sampler.state(1), DeviceState::Ok);
  EXPECT_EQ(sampler.take_change(), -1) << "at boot only a device that is not ok is news";
  r.chain.find(2)->fault = ServoFault::kError;
  r.chain.find(2)->error = dynamixel::p1::kOverload;
  sampler.poll(100);
  sampler.poll(100);
  EXPECT_EQ(sampler.state(1), DeviceState::Fault);
  EXPECT_EQ(sampler.take_change(), 1);
  const char* names[4];
  ASSERT_EQ(sampler.fault_names(1, names, 4), 1u);
  EXPECT_STREQ(names[0], "overload");
  float l[1] = {};
  EXPECT_EQ(sampler.fill(l, 100).invalid, 1u) << "a faulted servo's channels are invalid";
  EXPECT_STREQ(protocol::device_state_name(uint8_t(DeviceState::Fault)), "fault");
}

}  // namespace
}  // namespace nlsoft::fw::drivers
