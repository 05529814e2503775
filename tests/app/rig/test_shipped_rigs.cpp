// The shipped rig files: the paper's rigs as the paper gives them, each
// file in step with the hand-written plant that stands in for its rig, the
// stm32f4 pin table and the shipped model it names.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "app/model/model_store.hpp"
#include "host/rig/board_pins.hpp"
#include "host/rig/firmware_rig.hpp"
#include "host/rig/rig.hpp"
#include "app/model/train.hpp"
#include "host/rig/rig_params.hpp"
#include "app/rig/rig_pipeline.hpp"
#include "host/rig/rig_reference.hpp"
#include "shared/board_stm32f4.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::console {
namespace {

Rig shipped(const std::string& name) { return load_rig(std::string(NLSOFT_RIGS_DIR) + "/" + name + ".toml"); }

// The one place the tests know the shipped rigs: the paper's dimensions,
// rates and tunings ("Results"; msd's N and Lambda are ours, rigs/msd.toml
// says why), their tasks, and the INFO numbers protocol/PROTOCOL.md gives.
TEST(ShippedRigs, AreThePapersRigs) {
  struct Paper {
    const char* name;
    int m, n, w, info;
    double rate_hz;
    std::vector<double> Q, Lambda;
    double s, b, r, eps;
    int N, Nc;
    RefKind task;
  };
  const Paper papers[] = {
      {"msd", 1, 1, 0, 0, 1000.0, {1.0}, {4e-2}, 1e-20, 1e-5, 4e2, 1e-3, 100, 1, RefKind::Step},
      {"hasel", 6, 3, 18, 1, 130.0, {1e6, 2e6, 1e6}, {1, 1, 1, 1, 1, 1}, 1e-25, 1e-5, 4e2, 1.0 / 130, 3, 1,
       RefKind::Swirl},
      {"tendon", 2, 3, 11, 2, 120.0, {1e-3, 5e3, 2e3}, {1, 1}, 1e-20, 1e-10, 4e5, 1.0 / 120, 3, 3, RefKind::Infinity},
  };
  for (const Paper& p : papers) {
    SCOPED_TRACE(p.name);
    const Rig rig = shipped(p.name);
    EXPECT_EQ(rig.name, p.name);
    EXPECT_EQ(rig.m(), p.m);
    EXPECT_EQ(rig.n(), p.n);
    EXPECT_EQ(rig.w(), p.w);
    EXPECT_EQ(rig.nd, 2);
    EXPECT_EQ(rig.info_platform, p.info);
    EXPECT_EQ(firmware_rig(rig).platform, PlatformId(p.info));
    EXPECT_EQ(rig_plant_target(rig).platform, p.info);
    EXPECT_EQ(rig.rate_hz, p.rate_hz);
    EXPECT_EQ(rig.controller.Q, p.Q);
    EXPECT_EQ(rig.controller.Lambda, p.Lambda);
    EXPECT_EQ(rig.controller.s, p.s);
    EXPECT_EQ(rig.controller.b, p.b);
    EXPECT_EQ(rig.controller.r, p.r);
    EXPECT_NEAR(rig.controller.eps, p.eps, 1e-15);
    EXPECT_EQ(rig.controller.N, p.N);
    EXPECT_EQ(rig.controller.Nc, p.Nc);
    EXPECT_EQ(rig.controller.nr_max_iter, 1);  // as the paper's firmware ran
    EXPECT_EQ(rig.reference.kind, p.task);
    ASSERT_NE(rig.plant.kind, nullptr);
    EXPECT_STREQ(rig.plant.kind->name, p.name);
  }
}

class ShippedRig : public ::testing::TestWithParam<std::string> {
 protected:
  Rig rig = shipped(GetParam());
};

TEST_P(ShippedRig, LimitsNeutralAndOutputBoxAreThePlants) {
  SimPlant plant;
  ASSERT_TRUE(plant.select(rig.plant.kind->kind));
  float umin[kMaxPlantM], umax[kMaxPlantM], neutral[kMaxPlantM], lo[kMaxPlantN], hi[kMaxPlantN];
  plant.input_limits(umin, umax);
  plant.neutral_input(neutral);
  plant.output_box(lo, hi);
  for (int i = 0; i < rig.m(); ++i) {
    EXPECT_EQ(float(rig.inputs[size_t(i)].min), umin[i]) << i;
    EXPECT_EQ(float(rig.inputs[size_t(i)].max), umax[i]) << i;
    EXPECT_EQ(float(rig.inputs[size_t(i)].neutral), neutral[i]) << i;
  }
  for (int i = 0; i < rig.n(); ++i) {
    EXPECT_EQ(float(rig.outputs[size_t(i)].min), lo[i]) << i;
    EXPECT_EQ(float(rig.outputs[size_t(i)].max), hi[i]) << i;
  }
  EXPECT_EQ(float(1.0 / rig.rate_hz), plant.dt());
}

// Actuator i drives PWM row i, sensor i reads analogue row i; sensors beyond
// the table say so (source = "none") instead of reading a silent 0.
TEST_P(ShippedRig, PinsAreTheStm32f4Table) {
  namespace pins = fw::stm32f4;
  const BoardPins* board = find_board("stm32f4");
  ASSERT_NE(board, nullptr);
  EXPECT_EQ(rig.board, "stm32f4");
  for (int i = 0; i < rig.m(); ++i) EXPECT_EQ(rig.inputs[size_t(i)].pwm, board->pwm[size_t(i)]) << i;
  for (int i = 0; i < rig.w(); ++i) {
    const RigSensor& s = rig.sensors[size_t(i)];
    if (i < pins::kAnalogueCount) {
      EXPECT_EQ(s.source, SensorSource::Adc) << i;
      EXPECT_EQ(s.adc, pins::kAnalogue[i].adc_channel) << i;
      EXPECT_EQ(float(s.gain), pins::kAnalogue[i].gain) << i;
      EXPECT_EQ(float(s.offset), pins::kAnalogue[i].offset) << i;
    } else {
      EXPECT_EQ(s.source, SensorSource::None) << i;
    }
  }
}

TEST_P(ShippedRig, TheModelFileHasTheLayers) {
  const pipeline::ModelFile f = pipeline::load_model_file(std::string(NLSOFT_MODELS_DIR) + "/" + rig.model.file);
  ASSERT_EQ(size_t(f.shape.layer_count), rig.model.layers.size());
  EXPECT_EQ(f.shape.m, rig.m());
  EXPECT_EQ(f.shape.n, rig.n());
  EXPECT_EQ(f.shape.w, rig.w());
  EXPECT_EQ(f.shape.nd, rig.nd);
  for (size_t i = 0; i < rig.model.layers.size(); ++i) {
    const Layer& L = f.shape.layer[i];
    const RigLayer& R = rig.model.layers[i];
    EXPECT_EQ(R.kind, L.kind == LayerKind::Gru ? "gru" : "dense") << i;
    EXPECT_EQ(R.units, int(L.out)) << i;
    if (L.kind == LayerKind::Dense) {
      EXPECT_EQ(R.activation, pipeline::activation_name(L.act)) << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Rigs, ShippedRig, ::testing::Values("msd", "hasel", "tendon"),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

// hasel declares 18 sensors, the board brings out 13 analogue inputs: the
// other five are there, explicitly unwired, and a 14th analogue sensor
// cannot be declared (every channel is taken).
TEST(ShippedRigs, HaselsUnwiredSensorsAreExplicit) {
  const Rig rig = shipped("hasel");
  int none = 0;
  for (const RigSensor& s : rig.sensors) none += s.source == SensorSource::None;
  EXPECT_EQ(none, 18 - fw::stm32f4::kAnalogueCount);
}

}  // namespace
}  // namespace nlsoft::console
