// The plant model file (app/model/plant_model.hpp): what is written reads
// back the same, each size and channel is checked where the bytes become
// values, and the parts step as the firmware's forward pass steps a model.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/model/error.hpp"
#include "app/model/plant_model.hpp"
#include "shared/crc32.hpp"
#include "shared/forward.hpp"

namespace nlsoft::model {
namespace {

ModelFile msd_model() { return load_model_file(std::string(NLSOFT_SOURCE_DIR) + "/app/models/msd.nlsm"); }

// msd (m = 1, n = 1, w = 0): one part, its one channel, the shipped model.
PlantModel msd_plant() {
  PlantModel pm;
  pm.rig = "msd";
  pm.m = 1, pm.n = 1, pm.w = 0;
  pm.rate_hz = 1000;
  pm.fit = "free run: x RMSE 0.01 m";
  pm.parts.push_back({{0}, msd_model()});
  return pm;
}

std::string refusal(const std::vector<uint8_t>& bytes) {
  try {
    decode_plant_model(bytes, "p.nlsp");
  } catch (const PipelineError& e) {
    return e.what();
  }
  return "";
}

// The CRC-32 at the end made right again, so a check behind it is reached.
std::vector<uint8_t> resealed(std::vector<uint8_t> b) {
  b.resize(b.size() - 4);
  const uint32_t c = crc32(b.data(), b.size());
  for (int i = 0; i < 4; ++i) b.push_back(uint8_t(c >> (8 * i)));
  return b;
}

TEST(PlantModel, WhatIsWrittenReadsBackTheSame) {
  PlantModel pm = msd_plant();
  const std::vector<uint8_t> bytes = encode_plant_model(pm);
  PlantModel back = decode_plant_model(bytes, "p.nlsp");
  EXPECT_EQ(back.rig, "msd");
  EXPECT_EQ(back.fit, pm.fit);
  EXPECT_EQ(back.rate_hz, 1000.0);
  ASSERT_EQ(back.parts.size(), 1u);
  EXPECT_EQ(back.parts[0].outputs, std::vector<int>{0});
  EXPECT_EQ(back.parts[0].model.params, pm.parts[0].model.params);
  EXPECT_EQ(encode_plant_model(back), bytes);
}

TEST(PlantModel, EveryDamageIsRefusedNamingWhatIsWrong) {
  PlantModel pm = msd_plant();
  const std::vector<uint8_t> good = encode_plant_model(pm);
  std::vector<uint8_t> b = good;
  b[20] ^= 1;  // the rig's name
  EXPECT_NE(refusal(b).find("CRC-32 does not match"), std::string::npos) << refusal(b);
  b = good;
  b.resize(10);
  EXPECT_NE(refusal(b).find("no NLSP header"), std::string::npos) << refusal(b);
  b = good;
  b[4] = 9;
  EXPECT_NE(refusal(b).find("format 9"), std::string::npos) << refusal(b);
  // A model length past the file's end.
  b = good;
  const size_t len_at = 20 + pm.rig.size() + pm.fit.size() + 1 + 1;
  b[len_at + 3] = 0x7f;
  EXPECT_NE(refusal(resealed(b)).find("past the console's largest"), std::string::npos) << refusal(resealed(b));
  b[len_at + 3] = 0;
  b[len_at] = uint8_t(b[len_at] + 1);
  EXPECT_NE(refusal(resealed(b)).find("runs past its end"), std::string::npos) << refusal(resealed(b));
  // A channel past the plant's.
  b = good;
  b[len_at - 1] = 3;
  EXPECT_NE(refusal(resealed(b)).find("names channel 3 of 1"), std::string::npos) << refusal(resealed(b));
  // The rig's name longer than the file.
  b = good;
  b[16] = 0xff, b[17] = 0x0f;
  EXPECT_NE(refusal(resealed(b)).find("runs past its end"), std::string::npos) << refusal(resealed(b));
  // A controller's model file is no plant model.
  ModelFile f = msd_model();
  EXPECT_NE(refusal(encode_model(f)).find("no NLSP header"), std::string::npos);
}

TEST(PlantModel, AChannelPredictedTwiceOrNotAtAllIsRefused) {
  PlantModel twice = msd_plant();
  twice.parts.push_back(twice.parts[0]);
  EXPECT_NE(refusal(encode_plant_model(twice)).find("channel 0 is predicted by parts 1 and 2"), std::string::npos)
      << refusal(encode_plant_model(twice));
  PlantModel wider = msd_plant();
  wider.w = 1;
  EXPECT_NE(refusal(encode_plant_model(wider)).find("no part predicts channel 1"), std::string::npos)
      << refusal(encode_plant_model(wider));
  // A part that reads sensors: a controller's model of hasel.
  PlantModel hasel;
  hasel.rig = "hasel";
  hasel.m = 6, hasel.n = 3, hasel.w = 0;
  hasel.rate_hz = 130;
  hasel.parts.push_back({{0, 1, 2}, load_model_file(std::string(NLSOFT_SOURCE_DIR) + "/app/models/hasel.nlsm")});
  EXPECT_NE(refusal(encode_plant_model(hasel)).find("reads m = 6, n = 3, w = 18, not m = 6, n = 3, w = 0"),
            std::string::npos)
      << refusal(encode_plant_model(hasel));
}

// One part: a step of the plant is the model's forward pass on the history
// it keeps, newest first, as evaluate()'s free run feeds it.
TEST(PlantModel, ThePlantStepsAsTheModelsForwardPass) {
  const PlantModel pm = msd_plant();
  const Model<HostCapacity> M = pm.parts[0].model.view();
  ASSERT_EQ(M.nd, 2);
  ASSERT_EQ(M.dd, 2);
  PlantSimulator sim(pm);
  const float rest_y = 0.1f, rest_u = 0.0f;
  sim.rest_at(&rest_y, &rest_u);
  ForwardScratch<HostCapacity, float> scratch;
  float x[4] = {0, rest_u, rest_y, rest_y}, y = 0;  // u(k), u(k-1), y(k), y(k-1)
  const float inputs[] = {1.0f, 50.0f, -20.0f, 0.0f, 100.0f};
  for (float u : inputs) {
    x[1] = x[0], x[0] = u;
    forward(M, x, &y, scratch);
    sim.step(&u);
    x[3] = x[2], x[2] = y;
    EXPECT_EQ(sim.channels()[0], y) << "u " << u;
  }
  EXPECT_NE(sim.channels()[0], rest_y) << "the plant moved";
}

TEST(PlantModel, ChannelsArePartedAsAModelFileHoldsThem) {
  const auto parts = plant_parts(3, 18);
  ASSERT_EQ(parts.size(), 4u);
  EXPECT_EQ(parts[0], (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(parts[3], (std::vector<int>{18, 19, 20}));
  EXPECT_EQ(plant_parts(6, 32).size(), 7u);
  EXPECT_EQ(plant_parts(1, 0).size(), 1u);
}

}  // namespace
}  // namespace nlsoft::model
