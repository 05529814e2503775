// The model file: round trip, and every corruption refused before the
// caller's storage is touched.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "shared/forward.hpp"
#include "shared/model_file.hpp"
#include "support/random_model.hpp"

using namespace nlsoft;
using Cap = HostCapacity;

namespace {

std::vector<uint8_t> file_of(const Model<Cap>& M) {
  std::vector<uint8_t> buf(model_file_size(M.layer_count, M.param_count));
  EXPECT_EQ(write_model(M, 2, buf.data(), buf.size()), buf.size());
  return buf;
}

}  // namespace

TEST(ModelFile, RoundTripPreservesEveryBitAndTheOutput) {
  auto o = test::random_model<Cap>(2, 3, 11, 2,
                                   {{LayerKind::Gru, 5, Activation::Tanh, Activation::HardSigmoid, false},
                                    {LayerKind::Dense, 5, Activation::Relu},
                                    {LayerKind::Dense, 3, Activation::Tanh}},
                                   8, 0.5f, true);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  const auto buf = file_of(o.model);
  std::vector<float> storage(4096);
  Model<Cap> M;
  uint8_t platform = 0;
  ASSERT_EQ(parse_model(buf.data(), buf.size(), M, storage.data(), uint32_t(storage.size()), &platform), Status::Ok);
  EXPECT_EQ(platform, 2);
  EXPECT_EQ(M.param_count, o.model.param_count);
  EXPECT_EQ(std::memcmp(M.params, o.model.params, 4 * M.param_count), 0);
  EXPECT_TRUE(M.residual);
  EXPECT_FALSE(M.layer[0].reset_after);
  EXPECT_EQ(M.layer[0].rec_act, Activation::HardSigmoid);
  EXPECT_EQ(M.hash, crc32(buf.data(), buf.size() - 4));
  std::vector<float> x(M.p(), 0.25f);
  float y1[3], y2[3];
  static ForwardScratch<Cap, float> s;
  forward(o.model, x.data(), y1, s);
  forward(M, x.data(), y2, s);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(y1[i], y2[i]);
}

TEST(ModelFile, CorruptionIsRefusedAndStorageUntouched) {
  auto o = test::random_model<Cap>(1, 1, 0, 2, {{LayerKind::Dense, 3, Activation::Tanh},
                                                {LayerKind::Dense, 1, Activation::Linear}}, 2);
  ASSERT_EQ(finalize_model(o.model), Status::Ok);
  const auto good = file_of(o.model);
  std::vector<float> storage(512, 7.0f);
  Model<Cap> M;
  auto expect_refused = [&](std::vector<uint8_t> b, Status want, const char* what) {
    EXPECT_EQ(parse_model(b.data(), b.size(), M, storage.data(), 512), want) << what;
    for (float v : storage) ASSERT_EQ(v, 7.0f) << what;
    EXPECT_EQ(M.layer_count, 0) << what;
  };
  auto b = good;
  b[40] ^= 0x10;
  expect_refused(b, Status::BadChecksum, "flipped bit");
  expect_refused(std::vector<uint8_t>(good.begin(), good.end() - 5), Status::WrongSize, "truncated");
  b = good;
  b[0] = 'X';
  expect_refused(b, Status::BadFormat, "magic");
  auto reseal = [](std::vector<uint8_t>& v) {
    const uint32_t c = crc32(v.data(), v.size() - 4);
    for (int i = 0; i < 4; ++i) v[v.size() - 4 + i] = uint8_t(c >> (8 * i));
  };
  b = good;
  const float nan = std::nanf("");
  std::memcpy(&b[b.size() - 8], &nan, 4);
  reseal(b);
  expect_refused(b, Status::NotFinite, "NaN weight with a valid CRC");
  b = good;
  b[kModelHeaderSize + 8 + 4] = 9;  // second layer in = 9, chain broken
  reseal(b);
  expect_refused(b, Status::Inconsistent, "broken layer chain");
  b = good;
  b[kModelHeaderSize] = 7;  // unknown layer kind
  reseal(b);
  expect_refused(b, Status::UnknownId, "unknown layer kind");
  std::vector<float> tiny(4);
  EXPECT_EQ(parse_model(good.data(), good.size(), M, tiny.data(), 4), Status::TooLarge);
}
