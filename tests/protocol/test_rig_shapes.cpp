// RIG_INFO's shape list (PROTOCOL.md 7): made from the capacities the images
// are built with, read back, and the verdict on a model file's header that
// the console (before an upload) and the firmware (at XFER_BEGIN and the
// first chunk) both give.
#include <gtest/gtest.h>

#include <cstring>
#include <initializer_list>
#include <utility>
#include <vector>

#include "protocol/encoder.hpp"
#include "protocol/reply_cache.hpp"
#include "protocol/rig_shapes.hpp"
#include "support/rig_capacities.hpp"

namespace np = nlsoft::protocol;

namespace {

np::RigInfo rig(int m, int n, int w, int nd) {
  np::RigInfo r;
  r.m = uint8_t(m), r.n = uint8_t(n), r.w = uint8_t(w), r.nd = r.dd = uint8_t(nd);
  return r;
}
np::RigInfo hasel_rig() { return rig(6, 3, 18, 2); }

// A model file's header and layer table (what model_shape reads), for
// layers given as {kind, units}, with the size the whole file would have.
std::vector<uint8_t> model_header(int m, int n, int w, int nd, std::initializer_list<std::pair<int, int>> layers,
                                  bool reset_after = true) {
  std::vector<uint8_t> f(nlsoft::kModelHeaderSize + nlsoft::kModelLayerSize * layers.size());
  std::memcpy(f.data(), "NLSM", 4);
  namespace at = nlsoft::model_offset;
  f[at::kVersion] = 1;
  f[at::kM] = uint8_t(m), f[at::kN] = uint8_t(n), f[at::kW] = uint8_t(w), f[at::kNd] = f[at::kDd] = uint8_t(nd);
  f[at::kLayers] = uint8_t(layers.size());
  int in = nd * (m + n) + w, i = 0;
  for (const auto& [kind, units] : layers) {
    uint8_t* e = f.data() + nlsoft::kModelHeaderSize + nlsoft::kModelLayerSize * i++;
    e[0] = uint8_t(kind);
    e[3] = reset_after ? 1 : 0;
    e[4] = uint8_t(in), e[5] = uint8_t(in >> 8);
    e[6] = uint8_t(units), e[7] = uint8_t(units >> 8);
    in = units;
  }
  return f;
}

np::ModelShape shape_of(const std::vector<uint8_t>& header) {
  np::ModelShape s;
  EXPECT_TRUE(np::model_shape(header.data(), header.size(), s));
  return s;
}

TEST(RigShapes, TheHaselImageListsItsOneShapeAsTheGoldenVectorDoes) {
  np::RigInfo r = hasel_rig();
  ASSERT_TRUE(np::fill_accepted_shapes<nlsoft::HaselCapacity>(r));
  EXPECT_EQ(r.accept, np::shape_accept::kList);
  const std::vector<uint8_t> want = {3, 1, 5, 0, 1, 5, 0, 1, 3, 0};  // vector rig_info_hasel
  EXPECT_EQ(std::vector<uint8_t>(r.shapes, r.shapes + r.shapes_size), want);
  EXPECT_EQ(r.max_layers, 4);
  EXPECT_EQ(r.max_width, 5);
  EXPECT_EQ(r.max_weights, 233u);
  EXPECT_EQ(np::shape_count(r), 1);
  EXPECT_TRUE(np::shapes_well_formed(r.shapes, r.shapes_size));
}

TEST(RigShapes, ListsOnlyTheShapesForTheRigsDimensionsAndAGruByItsKind) {
  np::RigInfo t = rig(2, 3, 11, 2);
  ASSERT_TRUE(np::fill_accepted_shapes<nlsoft::TendonCapacity>(t));
  EXPECT_EQ(std::vector<uint8_t>(t.shapes, t.shapes + t.shapes_size),
            (std::vector<uint8_t>{3, 2, 5, 0, 1, 5, 0, 1, 3, 0}));
  // A capacity's shape for another rig is left out: no shape of msd's is one for hasel.
  uint8_t out[np::kMaxShapeBytes];
  EXPECT_EQ(np::write_shapes(nlsoft::ShapeList<nlsoft::MsdShape, nlsoft::HaselAuthorsShape>{}, 6, 3, 18, 2, out,
                             sizeof out),
            10u);
  EXPECT_EQ(out[1 + 1], 10);  // the authors' first layer, 10 units
  EXPECT_EQ(np::write_shapes(nlsoft::ShapeList<nlsoft::HaselShape>{}, 6, 3, 18, 2, out, 9), 0u) << "does not fit";
}

TEST(RigShapes, AGenericKernelTakesAnyShapeWithinItsLimits) {
  np::RigInfo r = hasel_rig();
  ASSERT_TRUE(np::fill_accepted_shapes<nlsoft::HostCapacity>(r));
  EXPECT_EQ(r.accept, np::shape_accept::kAny);
  EXPECT_EQ(r.shapes_size, 0);
  EXPECT_EQ(r.max_width, nlsoft::HostCapacity::width);
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 18, 2, {{1, 10}, {1, 5}, {1, 3}}))),
            np::ShapeVerdict::Accepted);
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 18, 2, {{1, 49}, {1, 3}}))), np::ShapeVerdict::TooWide);
  // A GRU's buffer is 3 x units: 17 units need 51 > 48.
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 18, 2, {{2, 17}, {1, 3}}))), np::ShapeVerdict::TooWide);
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 18, 2, {{1, 3}, {1, 3}, {1, 3}, {1, 3}, {1, 3}, {1, 3},
                                                                {1, 3}, {1, 3}, {1, 3}}))),
            np::ShapeVerdict::TooManyLayers);
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 18, 2, {{1, 48}, {1, 48}, {1, 48}, {1, 48}, {1, 3}}))),
            np::ShapeVerdict::TooManyWeights);
  EXPECT_EQ(np::accepts(r, shape_of(model_header(1, 1, 0, 2, {{1, 1}}))), np::ShapeVerdict::OtherDims);
}

TEST(RigShapes, AListedShapeIsTakenExactlyAndTheAuthorsShapeIsNot) {
  np::RigInfo r = hasel_rig();
  ASSERT_TRUE(np::fill_accepted_shapes<nlsoft::HaselCapacity>(r));
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 18, 2, {{1, 5}, {1, 5}, {1, 3}}))), np::ShapeVerdict::Accepted);
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 18, 2, {{1, 10}, {1, 5}, {1, 3}}))),
            np::ShapeVerdict::NotListed);
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 18, 2, {{2, 5}, {1, 5}, {1, 3}}))), np::ShapeVerdict::NotListed)
      << "a GRU where the list has a Dense layer";
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 18, 1, {{1, 5}, {1, 5}, {1, 3}}))), np::ShapeVerdict::NotListed)
      << "another history length is another kernel";
  EXPECT_EQ(np::accepts(r, shape_of(model_header(6, 3, 17, 2, {{1, 5}, {1, 5}, {1, 3}}))), np::ShapeVerdict::OtherDims);
}

TEST(RigShapes, BeginRefusesOnlySizesNoListedShapeCanHave) {
  np::RigInfo r = hasel_rig();
  ASSERT_TRUE(np::fill_accepted_shapes<nlsoft::HaselCapacity>(r));
  // Dense 36->5->5->3: 2p + 2n + 185 + 30 + 18 = 311 parameters.
  const uint32_t ours = uint32_t(nlsoft::model_file_size(3, 2 * 36 + 2 * 3 + 233));
  const uint32_t authors = uint32_t(nlsoft::model_file_size(3, 2 * 36 + 2 * 3 + 443));
  EXPECT_TRUE(np::size_fits_a_shape(r, ours));
  EXPECT_FALSE(np::size_fits_a_shape(r, authors));
  EXPECT_FALSE(np::size_fits_a_shape(r, ours + 4));
  // A GRU layer has one or two bias rows: both sizes of tendon's shape pass.
  np::RigInfo t = rig(2, 3, 11, 2);
  ASSERT_TRUE(np::fill_accepted_shapes<nlsoft::TendonCapacity>(t));
  const uint32_t two_rows = uint32_t(nlsoft::model_file_size(
      3, 2 * 21 + 6 + nlsoft::ShapeNeeds<nlsoft::TendonShape>::weights));
  EXPECT_TRUE(np::size_fits_a_shape(t, two_rows));
  EXPECT_TRUE(np::size_fits_a_shape(t, two_rows - 4 * 15));
  EXPECT_FALSE(np::size_fits_a_shape(t, two_rows + 4));
  // With accept = any, the size says nothing about the shape.
  np::RigInfo any = hasel_rig();
  ASSERT_TRUE(np::fill_accepted_shapes<nlsoft::HostCapacity>(any));
  EXPECT_TRUE(np::size_fits_a_shape(any, authors));
}

TEST(RigShapes, AMalformedListIsNotWellFormed) {
  const uint8_t cut[] = {3, 1, 5, 0, 1, 5, 0, 1, 3};
  const uint8_t zero_layers[] = {0};
  const uint8_t unknown_kind[] = {1, 7, 3, 0};
  const uint8_t no_units[] = {1, 1, 0, 0};
  EXPECT_FALSE(np::shapes_well_formed(cut, sizeof cut));
  EXPECT_FALSE(np::shapes_well_formed(zero_layers, sizeof zero_layers));
  EXPECT_FALSE(np::shapes_well_formed(unknown_kind, sizeof unknown_kind));
  EXPECT_FALSE(np::shapes_well_formed(no_units, sizeof no_units));
  EXPECT_TRUE(np::shapes_well_formed(nullptr, 0));
}

TEST(RigShapes, AFullRigInfoFitsTheReplyCache) {
  np::RigInfo r = hasel_rig();
  std::memset(r.rig_name, 'x', np::kRigNameLen);
  r.shapes_size = np::kMaxShapeBytes;
  uint8_t wire[np::kWireBufferSize];
  const size_t n = np::encode_reply(r, 1, wire, sizeof wire);
  ASSERT_NE(n, 0u);
  EXPECT_EQ(n, np::ReplyCache::kCapacity);
  r.shapes_size = np::kMaxShapeBytes + 1;
  EXPECT_EQ(np::encode_reply(r, 1, wire, sizeof wire), 0u) << "a longer list is not sent";
}

}  // namespace
