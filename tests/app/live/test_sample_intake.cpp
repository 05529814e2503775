// Sample intake's word on the sensor chips: the latest SENSOR_HEALTH, kept
// whether a run is recording or not (the status bar shows it either way).
#include <gtest/gtest.h>

#include <cmath>

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

// The live plots draw what the buffer holds: the channels SENSOR_HEALTH
// flags for the newest sample's step become NaN there (a gap in the plot),
// and a word for another step marks nothing.
TEST(SampleIntake, AnInvalidChannelIsAGapInTheLivePlotsNotTheZeroSent) {
  test::TempDir dir;
  Recorder recorder(dir.file("r.db"));
  ActiveRun run(recorder);
  SampleIntake intake(run, nullptr);
  protocol::IdentSample t{};
  t.step = 41;
  t.m = 1;
  t.n = 1;
  t.w = 3;
  intake.on_ident_sample(t, 0);
  protocol::SensorHealth h;
  h.step = 40;  // not the newest sample's
  h.invalid = 0x1u;
  intake.on_sensor_health(h);
  h.step = 41;
  h.invalid = 0x4u;
  intake.on_sensor_health(h);
  const std::vector<Sample> shown = intake.live().snapshot(1);
  ASSERT_EQ(shown.size(), 1u);
  ASSERT_EQ(shown[0].w, 3);
  EXPECT_EQ(shown[0].l[0], 0.0f);
  EXPECT_EQ(shown[0].l[1], 0.0f);
  EXPECT_TRUE(std::isnan(shown[0].l[2]));
}

}  // namespace
}  // namespace nlsoft::console
