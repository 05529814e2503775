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

protocol::Telemetry telemetry_at(uint32_t step) {
  protocol::Telemetry t{};
  t.mask = protocol::telemetry_field::kStep | protocol::telemetry_field::kU;
  t.n = 1;
  t.m = 1;
  t.step = step;
  t.u[0] = 0.5f;
  return t;
}

protocol::SensorSample sensors_at(uint32_t step, uint8_t w, float first) {
  protocol::SensorSample s{};
  s.step = step;
  s.w = w;
  for (int i = 0; i < w; ++i) s.l[i] = first + float(i);
  return s;
}

// Protocol 1.6: a closed-loop step's SENSOR_SAMPLE comes right before its
// TELEMETRY; the sample the plots (and the recorder) get carries its l.
// One of another step (its TELEMETRY lost), of another width, or sent
// while the console did not ask for them adds nothing.
TEST(SampleIntake, AClosedLoopStepCarriesTheSensorsSentBeforeItsTelemetry) {
  test::TempDir dir;
  Recorder recorder(dir.file("r.db"));
  ActiveRun run(recorder);
  SampleIntake intake(run, nullptr);
  run.sensors_w = 3;
  intake.on_sensor_sample(sensors_at(7, 3, 10.0f));
  intake.on_telemetry(telemetry_at(7), 0);
  intake.on_sensor_sample(sensors_at(7, 3, 20.0f));  // its TELEMETRY (step 7 again) lost: step 8 follows
  intake.on_telemetry(telemetry_at(8), 0);
  intake.on_sensor_sample(sensors_at(9, 2, 30.0f));  // not the width asked for
  intake.on_telemetry(telemetry_at(9), 0);
  intake.on_telemetry(telemetry_at(10), 0);  // no SENSOR_SAMPLE: the one of step 9 is not reused
  run.sensors_w = 0;
  intake.on_sensor_sample(sensors_at(11, 3, 40.0f));  // unasked
  intake.on_telemetry(telemetry_at(11), 0);
  const std::vector<Sample> shown = intake.live().snapshot(5);
  ASSERT_EQ(shown.size(), 5u);
  EXPECT_EQ(shown[0].step, 7u);
  ASSERT_EQ(shown[0].w, 3);
  EXPECT_EQ(shown[0].l[0], 10.0f);
  EXPECT_EQ(shown[0].l[2], 12.0f);
  for (size_t i = 1; i < shown.size(); ++i) EXPECT_EQ(shown[i].w, 0) << "step " << shown[i].step;
}

}  // namespace
}  // namespace nlsoft::console
