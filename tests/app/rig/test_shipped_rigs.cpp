// The shipped rig files: the paper's rigs as the paper gives them, each
// file in step with the hand-written plant that stands in for its rig, the
// stm32f4 pin table and the shipped model it names.
#include <gtest/gtest.h>

#include <algorithm>

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
#include "shared/chips/lis3mdl.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::console {

using host::BoardBus;
using host::BoardPins;
using host::Rig;
using host::RigDevice;
using host::RigLayer;
using host::RigSensor;
using host::SensorSource;
using host::find_board;
using host::firmware_rig;
using host::load_rig;

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

// The paper's PID baseline on msd ("PID controller that uses robust
// tuning"), with the output scale msd.toml explains; the other rigs have none.
TEST(ShippedRigs, MsdCarriesThePapersPidGains) {
  const Rig msd = shipped("msd");
  ASSERT_TRUE(msd.pid.given);
  EXPECT_EQ(msd.pid.kp, 1.93);
  EXPECT_EQ(msd.pid.ki, 4.01);
  EXPECT_EQ(msd.pid.kd, 5.99);
  EXPECT_EQ(msd.pid.output_scale, 60.0);
  EXPECT_EQ(msd.pid.d_filter_tau, 0.0);
  EXPECT_FALSE(shipped("hasel").pid.given);
  EXPECT_FALSE(shipped("tendon").pid.given);
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

// Actuator i drives PWM row i; a rig without chips reads sensor i on
// analogue row i, and sensors beyond the table say so (source = "none")
// instead of reading a silent 0; a rig with chips reads every sensor on them
// (hasel's, ShippedRigs.HaselReadsSixLis3mdlOnSpi2).
TEST_P(ShippedRig, PinsAreTheStm32f4Table) {
  namespace pins = fw::stm32f4;
  const BoardPins* board = find_board("stm32f4");
  ASSERT_NE(board, nullptr);
  EXPECT_EQ(rig.board, "stm32f4");
  // An input a servo drives has no PWM pin (tendon's two RX-64, ShippedRigs' own test).
  for (int i = 0; i < rig.m(); ++i)
    EXPECT_EQ(rig.inputs[size_t(i)].pwm, rig.inputs[size_t(i)].servo.empty() ? board->pwm[size_t(i)] : "") << i;
  for (int i = 0; i < rig.w(); ++i) {
    const RigSensor& s = rig.sensors[size_t(i)];
    const bool chips = std::any_of(rig.devices.begin(), rig.devices.end(),
                                   [](const RigDevice& d) { return !chips::on_serial(*d.chip); });
    if (chips) {
      EXPECT_EQ(s.source, SensorSource::Device) << i;
    } else if (i < pins::kAnalogueCount) {
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
  const model::ModelFile f = model::load_model_file(std::string(NLSOFT_MODELS_DIR) + "/" + rig.model.file);
  ASSERT_EQ(size_t(f.shape.layer_count), rig.model.layers.size());
  EXPECT_EQ(f.shape.m, rig.m());
  EXPECT_EQ(f.shape.n, rig.n());
  EXPECT_EQ(f.shape.w, rig.w());
  EXPECT_EQ(f.shape.nd, rig.nd);
  for (size_t i = 0; i < rig.model.layers.size(); ++i) {
    const Layer& L = f.shape.layer[i];
    const RigLayer& R = rig.model.layers[i];
    EXPECT_EQ(R.kind, L.kind) << i;
    EXPECT_EQ(R.units, int(L.out)) << i;
    if (L.kind == LayerKind::Dense) {
      EXPECT_EQ(R.activation, model::activation_name(L.act)) << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Rigs, ShippedRig, ::testing::Values("msd", "hasel", "tendon"),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

// hasel as the paper built it: six LIS3MDL on SPI2, one chip select each
// from the board's list, at +-16 gauss, read at the slowest rate above the
// loop's; sensor 3j + a is chip j's axis a, in gauss (0.01 gauss per uT),
// the scale of the simulated plant's channels (B_z of the own magnet 2 at rest).
TEST(ShippedRigs, HaselReadsSixLis3mdlOnSpi2) {
  const Rig rig = shipped("hasel");
  const BoardPins* board = find_board(rig.board);
  ASSERT_NE(board, nullptr);
  ASSERT_EQ(rig.devices.size(), 6u);
  double slowest_above_loop = 0;
  for (const chips::Setting& r : chips::lis3mdl::kRates)
    if (double(r.value) > rig.rate_hz && slowest_above_loop == 0) slowest_above_loop = double(r.value);
  for (size_t j = 0; j < rig.devices.size(); ++j) {
    SCOPED_TRACE(j);
    const RigDevice& d = rig.devices[j];
    EXPECT_EQ(d.chip, &chips::kLis3mdl);
    EXPECT_EQ(d.bus, "spi2");
    EXPECT_EQ(d.kind, BusKind::Spi);
    EXPECT_EQ(d.cs, board->chip_selects[j]);
    EXPECT_EQ(d.range, 16.0);
    EXPECT_EQ(d.range_bits, 0x60);  // CTRL_REG2 FS = +-16 gauss
    EXPECT_EQ(d.rate_hz, slowest_above_loop);
    EXPECT_EQ(d.clock_hz, 1000000u);  // the paper's
  }
  const BoardBus& spi2 = board->buses[size_t(rig.devices[0].bus_index)];
  EXPECT_EQ(spi2.pins, (std::vector<std::string>{"PB13", "PB14", "PB15"}));
  ASSERT_EQ(rig.sensors.size(), 18u);
  const char axes[] = "xyz";
  for (size_t i = 0; i < rig.sensors.size(); ++i) {
    SCOPED_TRACE(i);
    const RigSensor& s = rig.sensors[i];
    EXPECT_EQ(s.name, "b" + std::to_string(i / 3 + 1) + axes[i % 3]);
    EXPECT_EQ(s.source, SensorSource::Device);
    EXPECT_EQ(s.device, int(i / 3));
    EXPECT_EQ(s.channel, int(i % 3));
    EXPECT_EQ(s.unit, "gauss");
    EXPECT_EQ(s.gain, 0.01);
    EXPECT_EQ(s.offset, 0.0);
  }
}

}  // namespace
}  // namespace nlsoft::console
