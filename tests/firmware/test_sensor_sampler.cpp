// The sensor sampler over fake chips: what the step gets (values, invalid
// channels, age) as chips answer, go missing, answer wrongly, stop and come
// back; each state change reported once; a failed chip retried at most once
// a second; a chip read once per period of its rate.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "fake_chip.hpp"
#include "firmware/core/sensor_sampler.hpp"
#include "shared/chips/dps310.hpp"
#include "shared/chips/lis3mdl.hpp"

using namespace nlsoft;
using drivers_status = nlsoft::fw::drivers::ChipStatus;

namespace {

using test::FakeChip;

// Two chips: a magnetometer at 100 Hz (a sample every 10 ms) and a pressure
// sensor at 8 Hz (125 ms); four channels: mag z, pressure, an analogue
// channel the port reads, mag x scaled.
class Sampler : public ::testing::Test {
 protected:
  FakeChip mag_{3}, baro_{2};
  fw::drivers::Chip* chips_[2] = {&mag_, &baro_};
  const RigDeviceConfig devices_[2] = {
      {"tip", &chips::kLis3mdl, 0, BusKind::Spi, 0, 0, 1000000, {16.0f, 0x60}, {100.0f, 0x10}},
      {"air", &chips::kDps310, 1, BusKind::I2c, 0x77, 0, 100000, {0.0f, 0}, {8.0f, 0x30}},
  };
  const RigSensorSource sources_[4] = {
      {SensorFrom::Device, 0, 2, 1.0f, 0.0f},
      {SensorFrom::Device, 1, 0, 0.001f, 0.0f},
      {SensorFrom::Analogue, 0, 0, 1.0f, 0.0f},
      {SensorFrom::Device, 0, 0, 2.0f, 1.0f},
  };
  fw::SensorSampler::Slot slots_[2];
  fw::SensorSampler s_{chips_, devices_, slots_, 2, sources_, 4};
  float l_[4] = {-7.0f, -7.0f, 42.0f, -7.0f};

  std::vector<int> changes() {
    std::vector<int> out;
    for (int d; (d = s_.take_change()) >= 0;) out.push_back(d);
    return out;
  }
};

TEST_F(Sampler, TheStepGetsEachChannelScaledWithTheOldestSamplesAge) {
  mag_.reading[0] = 10.0f, mag_.reading[2] = -3.5f;
  baro_.reading[0] = 101325.0f;
  s_.begin(0);
  EXPECT_EQ(changes(), std::vector<int>{});  // every chip ok at boot: nothing to log
  s_.poll(1000);
  s_.poll(1004);  // the magnetometer's next sample is not due yet
  EXPECT_EQ(mag_.reads, 1);
  const fw::SensorHealth h = s_.fill(l_, 1004);
  EXPECT_EQ(h.invalid, 0u);
  EXPECT_EQ(h.age_ms, 4u);
  EXPECT_FLOAT_EQ(l_[0], -3.5f);
  EXPECT_FLOAT_EQ(l_[1], 101.325f);
  EXPECT_EQ(l_[2], 42.0f);  // the port's own channel is left as it read it
  EXPECT_FLOAT_EQ(l_[3], 21.0f);
  s_.poll(1010);
  EXPECT_EQ(mag_.reads, 2);
  EXPECT_EQ(baro_.reads, 1);  // 8 Hz: due again at 1125
  s_.poll(1125);
  EXPECT_EQ(baro_.reads, 2);
}

TEST_F(Sampler, AnAbsentChipIsInvalidNeverZeroAndRetriedOnceASecond) {
  baro_.begin_answer = drivers_status::kAbsent;
  s_.begin(0);
  EXPECT_EQ(changes(), std::vector<int>{1});
  EXPECT_EQ(s_.state(1), fw::DeviceState::Absent);
  for (uint32_t t = 1; t < 1000; t += 7) s_.poll(t);
  EXPECT_EQ(baro_.begins, 1);
  EXPECT_EQ(baro_.reads, 0);
  const fw::SensorHealth h = s_.fill(l_, 999);
  EXPECT_EQ(h.invalid, 1u << 1);
  EXPECT_EQ(s_.age_ms(1, 999), UINT32_MAX);
  s_.poll(1000);
  EXPECT_EQ(baro_.begins, 2);
  EXPECT_EQ(changes(), std::vector<int>{});  // still absent: no news
  baro_.begin_answer = drivers_status::kOk;
  baro_.reading[0] = 5000.0f;
  s_.poll(2000);
  EXPECT_EQ(s_.state(1), fw::DeviceState::Ok);
  EXPECT_EQ(changes(), std::vector<int>{1});
  s_.poll(2125);
  EXPECT_EQ(s_.fill(l_, 2125).invalid, 0u);
  EXPECT_FLOAT_EQ(l_[1], 5.0f);
  EXPECT_EQ(s_.faults(1), 2u);
}

TEST_F(Sampler, AChipThatAnswersWithAnotherIdentityIsWrongId) {
  mag_.begin_answer = drivers_status::kWrongId;
  s_.begin(0);
  EXPECT_EQ(s_.state(0), fw::DeviceState::WrongId);
  EXPECT_EQ(changes(), std::vector<int>{0});
  // The pressure sensor is ok but has no sample yet: invalid too.
  EXPECT_EQ(s_.fill(l_, 0).invalid, (1u << 0) | (1u << 1) | (1u << 3));
}

TEST_F(Sampler, AChipThatStopsAnsweringHoldsItsLastValueFlaggedInvalid) {
  mag_.reading[2] = 7.0f;
  s_.begin(0);
  s_.poll(10);
  mag_.read_answer = drivers_status::kBusFault;
  s_.poll(20);
  EXPECT_EQ(s_.state(0), fw::DeviceState::Stopped);
  EXPECT_EQ(changes(), std::vector<int>{0});
  const fw::SensorHealth h = s_.fill(l_, 25);
  EXPECT_EQ(h.invalid, (1u << 0) | (1u << 1) | (1u << 3));  // the 8 Hz chip's first sample is not due yet
  EXPECT_FLOAT_EQ(l_[0], 7.0f);  // the last good value, flagged
  EXPECT_EQ(s_.age_ms(0, 25), 15u);
}

TEST_F(Sampler, AChipWithNoNewSampleForFourPeriodsHasStopped) {
  s_.begin(0);
  s_.poll(10);
  mag_.read_answer = drivers_status::kNotReady;
  for (uint32_t t = 20; t < 150; t += 10) s_.poll(t);  // 4 x 10 ms + 100 ms after the sample at 10
  EXPECT_EQ(s_.state(0), fw::DeviceState::Ok);
  EXPECT_EQ(s_.fill(l_, 140).age_ms, 130u);
  s_.poll(150);
  EXPECT_EQ(s_.state(0), fw::DeviceState::Stopped);
  EXPECT_EQ(changes(), std::vector<int>{0});
}

}  // namespace
