// The shipped rig files against the compiled-in data they mirror (presets,
// simulated plants, reference presets, the stm32f4 pin table, the shipped
// models' shapes): while both exist, neither can drift from the other.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "app/model/model_store.hpp"
#include "app/rig/board_pins.hpp"
#include "app/rig/firmware_rig.hpp"
#include "app/rig/rig.hpp"
#include "app/model/train.hpp"
#include "app/rig/rig_params.hpp"
#include "app/rig/rig_pipeline.hpp"
#include "app/rig/rig_reference.hpp"
#include "firmware/ports/stm32f4/rig_pins.hpp"
#include "shared/platform.hpp"
#include "shared/reference_presets.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::console {
namespace {

class ShippedRig : public ::testing::TestWithParam<PlatformId> {
 protected:
  Rig rig = load_rig(std::string(NLSOFT_RIGS_DIR) + "/" + platform_name(GetParam()) + ".toml");
  const Preset& p = preset(GetParam());
};

TEST_P(ShippedRig, DimensionsAndRateAreThePresets) {
  EXPECT_EQ(rig.name, platform_name(GetParam()));
  EXPECT_EQ(rig.m(), p.m);
  EXPECT_EQ(rig.n(), p.n);
  EXPECT_EQ(rig.w(), p.w);
  EXPECT_EQ(rig.nd, p.nd);
  EXPECT_EQ(rig.dd, p.dd);
  EXPECT_EQ(float(rig.rate_hz), p.rate_hz);
  ASSERT_NE(rig.plant.kind, nullptr);
  EXPECT_STREQ(rig.plant.kind->name, platform_name(GetParam()));
}

TEST_P(ShippedRig, ControllerDefaultsAreThePresetsParameters) {
  Params<HostCapacity> want, got;
  ASSERT_EQ(preset_params(p, want), Status::Ok);
  ASSERT_EQ(rig_params(rig, got), Status::Ok);
  for (int i = 0; i < p.n; ++i) EXPECT_EQ(got.Q[i], want.Q[i]) << "Q[" << i << "]";
  for (int i = 0; i < p.m; ++i) {
    EXPECT_EQ(got.Lambda[i], want.Lambda[i]) << "Lambda[" << i << "]";
    EXPECT_EQ(got.u_min[i], want.u_min[i]) << "u_min[" << i << "]";
    EXPECT_EQ(got.u_max[i], want.u_max[i]) << "u_max[" << i << "]";
  }
  EXPECT_EQ(got.s, want.s);
  EXPECT_EQ(got.b, want.b);
  EXPECT_EQ(got.r, want.r);
  EXPECT_EQ(got.eps, want.eps);
  EXPECT_EQ(got.N, want.N);
  EXPECT_EQ(got.N1, want.N1);
  EXPECT_EQ(got.Nc, want.Nc);
  EXPECT_EQ(got.nr_tol, want.nr_tol);
  EXPECT_EQ(got.nr_max_iter, want.nr_max_iter);
  EXPECT_EQ(got.mode, want.mode);
  EXPECT_EQ(got.feedback, want.feedback);
}

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

// What the simulator serves for a rig file is what the images compiled for
// that rig hold, field for field, start-up reference included.
TEST_P(ShippedRig, TheFirmwaresRigDataFromTheFileIsTheCompiledIn) {
  const RigConfig got = firmware_rig(rig), want = shipped_rig(GetParam());
  EXPECT_STREQ(got.name, want.name);
  EXPECT_NE(got.hash, 0u);
  EXPECT_EQ(got.platform, want.platform);
  EXPECT_EQ(got.m, want.m);
  EXPECT_EQ(got.n, want.n);
  EXPECT_EQ(got.w, want.w);
  EXPECT_EQ(got.nd, want.nd);
  EXPECT_EQ(got.dd, want.dd);
  EXPECT_EQ(got.rate_hz, want.rate_hz);
  for (int i = 0; i < want.m; ++i) {
    EXPECT_EQ(got.u_min[i], want.u_min[i]) << i;
    EXPECT_EQ(got.u_max[i], want.u_max[i]) << i;
    EXPECT_EQ(got.u_neutral[i], want.u_neutral[i]) << i;
    EXPECT_EQ(got.Lambda[i], want.Lambda[i]) << i;
  }
  for (int i = 0; i < want.n; ++i) EXPECT_EQ(got.Q[i], want.Q[i]) << i;
  EXPECT_EQ(got.s, want.s);
  EXPECT_EQ(got.b, want.b);
  EXPECT_EQ(got.r, want.r);
  EXPECT_EQ(got.eps, want.eps);
  EXPECT_EQ(got.nr_tol, want.nr_tol);
  EXPECT_EQ(got.N, want.N);
  EXPECT_EQ(got.N1, want.N1);
  EXPECT_EQ(got.Nc, want.Nc);
  EXPECT_EQ(got.nr_max_iter, want.nr_max_iter);
  EXPECT_EQ(got.mode, want.mode);
  EXPECT_EQ(got.feedback, want.feedback);
  EXPECT_EQ(std::memcmp(&got.reference, &want.reference, sizeof got.reference), 0)
      << "start-up reference (kind " << int(got.reference.kind) << " vs " << int(want.reference.kind) << ")";
}

// `dataset --platform NAME` and `train --platform NAME` resolve to the
// shipped file: the pipeline must see in it exactly the compiled-in
// platform (same plant, limits, history, network, training options).
TEST_P(ShippedRig, PipelineTargetIsTheCompiledInPlatforms) {
  const pipeline::PlantTarget got = rig_plant_target(rig), want = pipeline::platform_target(GetParam());
  EXPECT_EQ(got.plant, pipeline::TargetPlant::Named);
  EXPECT_EQ(got.platform, uint8_t(GetParam()));
  EXPECT_EQ(got.kind, want.kind);
  EXPECT_EQ(got.m, want.m);
  EXPECT_EQ(got.n, want.n);
  EXPECT_EQ(got.w, want.w);
  EXPECT_EQ(got.nd, want.nd);
  for (int i = 0; i < got.m; ++i) {
    EXPECT_EQ(float(got.u_lo[size_t(i)]), float(want.u_lo[size_t(i)])) << i;
    EXPECT_EQ(float(got.u_hi[size_t(i)]), float(want.u_hi[size_t(i)])) << i;
  }
  const pipeline::TrainOptions a = pipeline::default_options(got), b = pipeline::default_options(GetParam());
  ASSERT_EQ(a.layers.size(), b.layers.size());
  for (size_t l = 0; l < a.layers.size(); ++l) {
    EXPECT_EQ(a.layers[l].kind, b.layers[l].kind) << l;
    EXPECT_EQ(a.layers[l].units, b.layers[l].units) << l;
    EXPECT_EQ(a.layers[l].act, b.layers[l].act) << l;
    EXPECT_EQ(a.layers[l].rec_act, b.layers[l].rec_act) << l;
    EXPECT_EQ(a.layers[l].reset_after, b.layers[l].reset_after) << l;
  }
  EXPECT_EQ(a.nd, b.nd);
  EXPECT_EQ(a.dd, b.dd);
  EXPECT_EQ(a.residual, b.residual);
  EXPECT_EQ(a.y_noise, b.y_noise);
}

TEST_P(ShippedRig, ReferencesAreThePresetPaths) {
  EXPECT_EQ(rig.reference.kind, default_reference_kind(GetParam()));
  for (RefKind k : {RefKind::Infinity, RefKind::Pringle, RefKind::Diagonal, RefKind::Swirl, RefKind::Step,
                    RefKind::Hold}) {
    const RefParams want = reference_preset(GetParam(), k), got = rig_reference(rig, k);
    EXPECT_EQ(std::memcmp(&want, &got, sizeof want), 0) << "kind " << int(k);
  }
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

INSTANTIATE_TEST_SUITE_P(Rigs, ShippedRig, ::testing::Values(PlatformId::Msd, PlatformId::Hasel, PlatformId::Tendon),
                         [](const ::testing::TestParamInfo<PlatformId>& p) { return std::string(platform_name(p.param)); });

// hasel declares 18 sensors, the board brings out 13 analogue inputs: the
// other five are there, explicitly unwired, and a 14th analogue sensor
// cannot be declared (every channel is taken).
TEST(ShippedRigs, HaselsUnwiredSensorsAreExplicit) {
  const Rig rig = load_rig(std::string(NLSOFT_RIGS_DIR) + "/hasel.toml");
  int none = 0;
  for (const RigSensor& s : rig.sensors) none += s.source == SensorSource::None;
  EXPECT_EQ(none, 18 - fw::stm32f4::kAnalogueCount);
}

}  // namespace
}  // namespace nlsoft::console
