// Sample intake's word on the sensor chips: the latest SENSOR_HEALTH, kept
// whether a run is recording or not (the status bar shows it either way).
#include <gtest/gtest.h>

#include "app/live/sample_intake.hpp"
#include "app/record/recorder.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

TEST(SampleIntake, KeepsTheLatestSensorHealthWithNoRunRecording) {
  test::TempDir dir;
  Recorder recorder(dir.file("r.db"));
  ActiveRun run(recorder);
  SampleIntake intake(run, nullptr);
  EXPECT_FALSE(intake.health().known);
  protocol::SensorHealth h;
  h.step = 40;
  h.invalid = 0x80000001u;
  h.age_ms = 517;
  intake.on_sensor_health(h);
  SampleIntake::Health got = intake.health();
  EXPECT_TRUE(got.known);
  EXPECT_EQ(got.invalid, 0x80000001u);
  EXPECT_EQ(got.age_ms, 517);
  EXPECT_GE(got.received_s_ago, 0.0);
  h.invalid = 0;
  h.age_ms = 65535;
  intake.on_sensor_health(h);
  got = intake.health();
  EXPECT_EQ(got.invalid, 0u);
  EXPECT_EQ(got.age_ms, 65535);
}

}  // namespace
}  // namespace nlsoft::console
