// The firmware core built as the hasel MCU image is (HaselCapacity: one
// shaped kernel, no generic one), on the host with an in-memory port:
// RIG_INFO lists the image's one shape, and a model of another shape is
// refused at XFER_BEGIN when its size tells, else at the chunk that brings
// its header (PROTOCOL.md 7 RIG_INFO, 9.4), not only at XFER_COMMIT.
#include <gtest/gtest.h>

#include <cstring>
#include <deque>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "memory_hal.hpp"
#include "firmware/core/firmware.hpp"
#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"
#include "shared/capacity.hpp"
#include "shared/crc32.hpp"
#include "shared/model_file.hpp"
#include "support/rig_capacities.hpp"
#include "support/shipped_rigs.hpp"

using namespace nlsoft;
namespace proto = nlsoft::protocol;

namespace {

using test::MemoryHal;

using HaselFw = fw::Firmware<HaselCapacity>;

class HaselImage : public ::testing::Test {
 protected:
  RigConfig rig_{};
  void SetUp() override {
    rig_ = test::shipped_config("hasel");
    rig_.hash = 0x5A17C0DEu;
    const fw::Identity id{&rig_, "nlsoft-test", 0, 1, 0, 130, false};
    const fw::Buffers b{staging_, sizeof staging_, table_, sizeof table_, points_, 30};
    fw_ = std::make_unique<HaselFw>(hal_, id, b);
    ASSERT_EQ(fw_->begin(nullptr, 0), Status::Ok);
  }

  // One request, its reply (REPLY flag and the request's seq).
  template <class M>
  std::pair<uint8_t, std::vector<uint8_t>> request(const M& m) {
    uint8_t wire[proto::kWireBufferSize];
    const size_t n = proto::encode(m, ++seq_, 0, wire, sizeof wire);
    EXPECT_NE(n, 0u);
    hal_.in.insert(hal_.in.end(), wire, wire + n);
    hal_.out.clear();
    fw_->poll();
    proto::Decoder dec;
    size_t used = 0;
    while (used < hal_.out.size()) {
      proto::DecodeResult r;
      used += dec.feed(hal_.out.data() + used, hal_.out.size() - used, r);
      if (r.kind == proto::DecodeResult::Kind::Frame && r.frame.is_reply() && r.frame.header.seq == seq_)
        return {r.frame.header.type, std::vector<uint8_t>(r.frame.payload, r.frame.payload + r.frame.header.length)};
    }
    ADD_FAILURE() << "no reply";
    return {};
  }
  template <class R, class M>
  R expect(const M& m) {
    const auto [type, payload] = request(m);
    R r;
    EXPECT_EQ(type, uint8_t(R::kType)) << proto::message_name(type);
    if (type == uint8_t(R::kType)) {
      EXPECT_EQ(proto::unpack(payload.data(), payload.size(), r), proto::StatusCode::Ok);
    }
    return r;
  }

  MemoryHal hal_;
  alignas(4) uint8_t staging_[model_file_max<HaselCapacity>()];
  uint8_t table_[8 + 4 * 3 * 10];
  float points_[30];
  std::unique_ptr<HaselFw> fw_;
  uint8_t seq_ = 0;
};

// A dense model file of hasel's dimensions (36 inputs) with these layer
// sizes; zero weights.
std::vector<uint8_t> dense_model(std::vector<int> units, int w = 18) {
  const int m = 6, n = 3, nd = 2, p = nd * (m + n) + w;
  uint32_t params = uint32_t(2 * p + 2 * n);
  int in = p;
  for (int u : units) params += uint32_t(in * u + u), in = u;
  std::vector<uint8_t> f(model_file_size(int(units.size()), params));
  std::memcpy(f.data(), "NLSM", 4);
  namespace at = model_offset;
  f[at::kVersion] = 1, f[at::kM] = m, f[at::kN] = n, f[at::kW] = uint8_t(w), f[at::kNd] = f[at::kDd] = nd;
  f[at::kLayers] = uint8_t(units.size());
  f[at::kPlatform] = 255;
  for (int i = 0; i < 4; ++i) f[at::kParams + i] = uint8_t(params >> (8 * i));
  in = p;
  for (size_t l = 0; l < units.size(); ++l) {
    uint8_t* e = f.data() + kModelHeaderSize + kModelLayerSize * l;
    e[0] = 1, e[1] = l + 1 < units.size() ? 2 : 0;
    e[4] = uint8_t(in), e[6] = uint8_t(units[l]);
    in = units[l];
  }
  const uint32_t crc = crc32(f.data(), f.size() - 4);
  for (int i = 0; i < 4; ++i) f[f.size() - 4 + i] = uint8_t(crc >> (8 * i));
  return f;
}

proto::XferBegin begin_of(const std::vector<uint8_t>& file) {
  proto::XferBegin b;
  b.kind = uint8_t(proto::XferKind::Model);
  b.total_size = uint32_t(file.size());
  b.crc32 = crc32(file.data(), file.size());
  return b;
}
proto::XferChunk chunk_of(const std::vector<uint8_t>& file, uint32_t offset) {
  proto::XferChunk c;
  c.kind = uint8_t(proto::XferKind::Model);
  c.offset = offset;
  c.size = uint8_t(std::min<size_t>(proto::kMaxChunkData, file.size() - offset));
  std::memcpy(c.data, file.data() + offset, c.size);
  return c;
}

TEST_F(HaselImage, RigInfoNamesTheRigAndListsTheImagesOneShape) {
  const auto ex = expect<proto::InfoEx>(proto::InfoGet{});
  EXPECT_EQ(ex.protocol_minor, proto::kProtocolMinor);
  EXPECT_TRUE(ex.info.capabilities & proto::capability::kRig);
  const auto r = expect<proto::RigInfo>(proto::RigGet{});
  EXPECT_STREQ(r.rig_name, "hasel");
  EXPECT_EQ(r.rig_hash, 0x5A17C0DEu);
  EXPECT_EQ(r.m, ex.info.m);
  EXPECT_EQ(r.n, ex.info.n);
  EXPECT_EQ(r.w, ex.info.w);
  EXPECT_EQ(r.nd, ex.info.nd);
  EXPECT_EQ(r.dd, ex.info.dd);
  EXPECT_EQ(r.accept, proto::shape_accept::kList);
  EXPECT_EQ(std::vector<uint8_t>(r.shapes, r.shapes + r.shapes_size),
            (std::vector<uint8_t>{3, 1, 5, 0, 1, 5, 0, 1, 3, 0}));
}

// A smaller shape fits the buffer the image's own shape needs; its size is
// no listed shape's. (The authors' 36->10->5->3 is larger than that buffer:
// too_large, by the size rule that comes first.)
TEST_F(HaselImage, AnotherShapeIsRefusedAtBeginByItsSize) {
  const auto narrower = dense_model({4, 5, 3});
  const auto n = expect<proto::Nack>(begin_of(narrower));
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::Unsupported));
  EXPECT_EQ(n.field, 2);
  // nothing opened: a chunk finds no transfer
  EXPECT_EQ(expect<proto::Nack>(chunk_of(narrower, 0)).status, uint8_t(proto::StatusCode::XferNotOpen));
  EXPECT_EQ(expect<proto::Nack>(begin_of(dense_model({10, 5, 3}))).status, uint8_t(proto::StatusCode::TooLarge));
  // the image's own shape begins, and commits
  const auto ours = dense_model({5, 5, 3});
  expect<proto::XferAck>(begin_of(ours));
  for (uint32_t at = 0; at < ours.size();) at = expect<proto::XferAck>(chunk_of(ours, at)).next_offset;
  proto::XferCommit c;
  c.kind = uint8_t(proto::XferKind::Model);
  expect<proto::Ack>(c);
  EXPECT_EQ(expect<proto::InfoEx>(proto::InfoGet{}).info.model_hash, crc32(ours.data(), ours.size() - 4));
}

// Section 9.4's order: the size rules first, so a model above model_max is
// too_large (the INFO_EX limit the console names), not unsupported.
TEST_F(HaselImage, AModelAboveModelMaxIsTooLargeBeforeItsShapeIsLookedAt) {
  const auto ex = expect<proto::InfoEx>(proto::InfoGet{});
  proto::XferBegin b;
  b.kind = uint8_t(proto::XferKind::Model);
  b.total_size = ex.model_max + 1;
  const auto n = expect<proto::Nack>(b);
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::TooLarge));
  EXPECT_EQ(n.field, 2);
  b.total_size = 0;
  EXPECT_EQ(expect<proto::Nack>(b).status, uint8_t(proto::StatusCode::OutOfRange));
}

TEST_F(HaselImage, AShapeOfTheSameSizeIsRefusedAtTheChunkThatBringsItsHeader) {
  // Dense 36->2->26->3 has 233 weights as 36->5->5->3 does: the size passes.
  const auto same_size = dense_model({2, 26, 3});
  ASSERT_EQ(same_size.size(), dense_model({5, 5, 3}).size());
  expect<proto::XferAck>(begin_of(same_size));
  const auto n = expect<proto::Nack>(chunk_of(same_size, 0));
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::Unsupported));
  EXPECT_EQ(n.field, 2);
  proto::XferCommit c;
  c.kind = uint8_t(proto::XferKind::Model);
  EXPECT_EQ(expect<proto::Nack>(c).status, uint8_t(proto::StatusCode::XferNotOpen)) << "the transfer was discarded";
  EXPECT_EQ(expect<proto::InfoEx>(proto::InfoGet{}).info.model_hash, 0u) << "no model came into force";
}

TEST_F(HaselImage, AHeaderOfAnotherPlantIsInconsistentAtItsChunk) {
  // w = 17 and a first layer of 6 units: the same file size as hasel's own shape.
  auto other = dense_model({5, 5, 3});
  other[model_offset::kW] = 17;
  const uint32_t crc = crc32(other.data(), other.size() - 4);
  for (int i = 0; i < 4; ++i) other[other.size() - 4 + i] = uint8_t(crc >> (8 * i));
  expect<proto::XferAck>(begin_of(other));
  const auto n = expect<proto::Nack>(chunk_of(other, 0));
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::Inconsistent));
  EXPECT_EQ(n.field, 2);
}

TEST_F(HaselImage, AHeaderSplitOverChunksIsCheckedWhenItIsWhole) {
  const auto same_size = dense_model({2, 26, 3});
  expect<proto::XferAck>(begin_of(same_size));
  proto::XferChunk first = chunk_of(same_size, 0);
  first.size = 30;  // header, and the first layer's entry cut
  EXPECT_EQ(expect<proto::XferAck>(first).next_offset, 30u);
  const auto n = expect<proto::Nack>(chunk_of(same_size, 30));
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::Unsupported));
}

// A header naming more layers than any shape list can hold (or max_layers
// allow) is refused unsupported at the chunk that completes it, as any
// other refused shape: COMMIT would have said too_large.
TEST_F(HaselImage, AHeaderOfMoreLayersThanAListCanNameIsUnsupportedAtItsChunk) {
  const auto own = dense_model({5, 5, 3});
  std::vector<uint8_t> deep(own.size(), 0);  // the size of the listed shape: BEGIN lets it in
  std::memcpy(deep.data(), own.data(), kModelHeaderSize);
  const int layers = proto::kMaxShapeLayers + 5;
  deep[model_offset::kLayers] = uint8_t(layers);
  const uint32_t params = uint32_t((deep.size() - 4 - kModelHeaderSize - kModelLayerSize * layers) / 4);
  for (int i = 0; i < 4; ++i) deep[model_offset::kParams + i] = uint8_t(params >> (8 * i));
  for (int l = 0; l < layers; ++l) deep[kModelHeaderSize + kModelLayerSize * size_t(l)] = 1;
  ASSERT_EQ(deep.size(), model_file_size(layers, params));
  expect<proto::XferAck>(begin_of(deep));
  EXPECT_EQ(expect<proto::XferAck>(chunk_of(deep, 0)).next_offset, proto::kMaxChunkData) << "header not whole yet";
  const auto n = expect<proto::Nack>(chunk_of(deep, proto::kMaxChunkData));
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::Unsupported));
  EXPECT_EQ(n.field, 2);
  proto::XferCommit c;
  c.kind = uint8_t(proto::XferKind::Model);
  EXPECT_EQ(expect<proto::Nack>(c).status, uint8_t(proto::StatusCode::XferNotOpen)) << "the transfer was discarded";
}

// A generic kernel (the simulator's) may still serve a list: accept 0 with
// the capacity's shapes for the rig's dimensions, the limits unchanged.
TEST(RigInfo, AGenericKernelServesItsShapesAsAListWhenAsked) {
  const RigConfig hasel = test::shipped_config("hasel");
  const proto::RigInfo any = fw::rig_info<HostCapacity>("hasel", 1, hasel);
  EXPECT_EQ(any.accept, proto::shape_accept::kAny);
  EXPECT_EQ(any.shapes_size, 0);
  const proto::RigInfo list = fw::rig_info<HostCapacity>("hasel", 1, hasel, true);
  EXPECT_EQ(list.accept, proto::shape_accept::kList);
  EXPECT_EQ(proto::shape_count(list), 2) << "hasel's own shape and the authors'";
  EXPECT_TRUE(proto::shapes_well_formed(list.shapes, list.shapes_size));
  EXPECT_EQ(list.max_layers, any.max_layers);
  EXPECT_EQ(list.max_width, any.max_width);
  EXPECT_EQ(list.max_weights, any.max_weights);
  EXPECT_TRUE(proto::size_fits_a_shape(list, uint32_t(dense_model({5, 5, 3}).size())));
  EXPECT_FALSE(proto::size_fits_a_shape(list, uint32_t(dense_model({6, 5, 3}).size())));
}

}  // namespace
