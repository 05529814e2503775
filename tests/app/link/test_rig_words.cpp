// What the console says about RIG_INFO (protocol 1.2): a model of a shape
// the firmware does not accept, in the words the operator reads before
// anything is sent; the rig file's hash and the warning when the firmware
// names another rig.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "app/link/model_shape_words.hpp"
#include "app/link/rig_hash.hpp"
#include "host/rig/rig.hpp"
#include "support/rig_capacities.hpp"
#include "shared/crc32.hpp"
#include "shared/model_file.hpp"

namespace nlsoft::console {

using host::rig_file_hash;

namespace {

namespace p = nlsoft::protocol;

template <class Cap>
p::RigInfo rig_of(const char* name, int m, int n, int w, int nd) {
  p::RigInfo r;
  std::snprintf(r.rig_name, sizeof r.rig_name, "%s", name);
  r.m = uint8_t(m), r.n = uint8_t(n), r.w = uint8_t(w), r.nd = r.dd = uint8_t(nd);
  EXPECT_TRUE(p::fill_accepted_shapes<Cap>(r));
  return r;
}

// A model file's header and layer table, {kind, units} per layer.
std::vector<uint8_t> header(int m, int n, int w, int nd, std::initializer_list<std::pair<int, int>> layers) {
  std::vector<uint8_t> f(kModelHeaderSize + kModelLayerSize * layers.size());
  std::memcpy(f.data(), "NLSM", 4);
  namespace at = model_offset;
  f[at::kVersion] = kModelFormatVersion;
  f[at::kM] = uint8_t(m), f[at::kN] = uint8_t(n), f[at::kW] = uint8_t(w), f[at::kNd] = f[at::kDd] = uint8_t(nd);
  f[at::kLayers] = uint8_t(layers.size());
  size_t i = 0;
  for (const auto& [kind, units] : layers) {
    uint8_t* e = f.data() + kModelHeaderSize + kModelLayerSize * i++;
    e[0] = uint8_t(kind), e[3] = 1, e[6] = uint8_t(units);
  }
  return f;
}

TEST(ModelShapeWords, TheAuthorsModelOnTheHaselImageIsRefusedInOneSentence) {
  const p::RigInfo hasel = rig_of<HaselCapacity>("hasel", 6, 3, 18, 2);
  const auto r = shape_refusal("model.nlsm", header(6, 3, 18, 2, {{1, 10}, {1, 5}, {1, 3}}), hasel);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(*r, "model.nlsm is Dense 36->10->5->3; this firmware (rig hasel) accepts Dense 36->5->5->3 only");
  EXPECT_FALSE(shape_refusal("ours.nlsm", header(6, 3, 18, 2, {{1, 5}, {1, 5}, {1, 3}}), hasel).has_value());
}

TEST(ModelShapeWords, AGruIsNamedLayerByLayerAndLimitsAreSaid) {
  const p::RigInfo tendon = rig_of<TendonCapacity>("tendon", 2, 3, 11, 2);
  EXPECT_EQ(accepted_words(tendon), "21->GRU(5)->Dense(5)->Dense(3) only");
  const p::RigInfo sim = rig_of<HostCapacity>("hasel", 6, 3, 18, 2);
  const auto r = shape_refusal("wide.nlsm", header(6, 3, 18, 2, {{1, 49}, {1, 3}}), sim);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(*r, "wide.nlsm is Dense 36->49->3 (a layer 49 wide); this firmware (rig hasel) accepts any shape within "
                "8 layers, 48 wide (a GRU layer 3 x its units), 8192 weights");
}

TEST(ModelShapeWords, WhatIsNotAModelHeaderOrForAnotherPlantIsLeftToTheOtherChecks) {
  const p::RigInfo hasel = rig_of<HaselCapacity>("hasel", 6, 3, 18, 2);
  auto junk = header(6, 3, 18, 2, {{1, 10}, {1, 5}, {1, 3}});
  junk[0] = 'X';
  EXPECT_FALSE(shape_refusal("junk", junk, hasel).has_value());
  EXPECT_FALSE(shape_refusal("msd.nlsm", header(1, 1, 0, 2, {{1, 1}}), hasel).has_value());
}

TEST(RigHash, LayoutCommentLinesAndLineEndingsDoNotChangeTheHash) {
  const std::string text = "name = \"hasel\"\nrate_hz = 130\n";
  const uint32_t h = rig_file_hash(text);
  EXPECT_EQ(h, crc32(reinterpret_cast<const uint8_t*>(text.data()), text.size())) << "canonical text is itself";
  EXPECT_EQ(rig_file_hash("# the HASEL rig\r\n\r\nname = \"hasel\"   \r\n   # rate\nrate_hz = 130"), h);
  EXPECT_NE(rig_file_hash("name = \"hasel\"\nrate_hz = 120\n"), h);
  EXPECT_NE(rig_file_hash("name = \"hasel\" # ours\nrate_hz = 130\n"), h) << "a comment after a value is content";
}

// The example of PROTOCOL.md 7 (CRs, trailing blanks, blank and comment
// lines) names its own hash on a comment line; the Python peer written from
// the document (check_vectors.py) computes the same.
TEST(RigHash, TheProtocolsExampleRigFileHasTheHashItNames) {
  std::ifstream in(NLSOFT_RIGS_DIR "/../protocol/vectors/rig_hash_example.toml", std::ios::binary);
  ASSERT_TRUE(in);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_NE(text.find("\r\n"), std::string::npos) << "the example keeps its CRs";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, std::regex("# rig_hash 0x([0-9a-f]{8})")));
  EXPECT_EQ(rig_file_hash(text), uint32_t(std::stoul(m[1], nullptr, 16)));
}

TEST(RigHash, AnotherRigOrHashIsAWarningAnUnknownHashIsNot) {
  RigFileId file{"rigs/hasel.toml", "hasel", 0xfeedbeefu};
  p::RigInfo rig;
  std::snprintf(rig.rig_name, sizeof rig.rig_name, "hasel");
  EXPECT_EQ(rig_mismatch(rig, file), "") << "hash 0: the image names no rig file";
  rig.rig_hash = 0xfeedbeefu;
  EXPECT_EQ(rig_mismatch(rig, file), "");
  rig.rig_hash = 0x12345678u;
  EXPECT_EQ(rig_mismatch(rig, file),
            "warning: the firmware's rig hasel has hash 12345678, rigs/hasel.toml has feedbeef: the image was built "
            "from another version of the rig file");
  std::snprintf(rig.rig_name, sizeof rig.rig_name, "tendon");
  EXPECT_NE(rig_mismatch(rig, file).find("the firmware runs rig tendon"), std::string::npos);
}

}  // namespace
}  // namespace nlsoft::console
