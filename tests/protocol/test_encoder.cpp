#include <gtest/gtest.h>

#include "protocol/encoder.hpp"
#include "protocol/messages.hpp"
#include "test_util.hpp"

namespace np = nlsoft::protocol;
using namespace nlsoft::protocol::test;

namespace {

TEST(Encoder, ReplyEchoesTheRequestSeqAndSetsTheReplyFlag) {
  np::Ack ack;
  ack.request_type = static_cast<uint8_t>(np::MsgType::RunStop);
  uint8_t buf[np::kWireBufferSize];
  const size_t n = np::encode_reply(ack, 200, buf, sizeof buf);
  ASSERT_GT(n, 0u);
  const auto events = decode_all(Bytes(buf, buf + n));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].header.seq, 200);
  EXPECT_EQ(events[0].header.flags, np::frame_flags::kReply);
  EXPECT_EQ(events[0].header.version, np::kProtocolVersion);
}

TEST(Encoder, OnlyTheLastWireByteIsZero) {
  np::XferChunk c;
  c.size = 200;  // all-zero data: the worst case for stuffing
  const Bytes w = wire_of(c);
  ASSERT_FALSE(w.empty());
  for (size_t i = 0; i + 1 < w.size(); ++i) ASSERT_NE(w[i], 0) << i;
  EXPECT_EQ(w.back(), 0);
}

TEST(Encoder, LargestFrameFitsTheRecommendedBuffer) {
  np::XferChunk c;
  c.size = np::kMaxChunkData;
  for (auto& b : c.data) b = 0xEE;
  uint8_t buf[np::kWireBufferSize];
  const size_t n = np::encode(c, 1, 0, buf, sizeof buf);
  EXPECT_EQ(n, np::kMaxWireFrame);
  EXPECT_EQ(np::encode(c, 1, 0, buf, np::kMaxWireFrame - 1), 0u);
}

TEST(Encoder, RefusesPayloadsOverTheMaximum) {
  const Bytes payload(np::kMaxPayload + 1, 1);
  uint8_t buf[512];
  np::Header h;
  h.type = static_cast<uint8_t>(np::MsgType::XferChunk);
  EXPECT_EQ(np::encode_frame_raw(h, payload.data(), payload.size(), 0, buf, sizeof buf), 0u);
}

TEST(Encoder, RefusesUnknownTypesAndLengthsTheTypeDoesNotAllow) {
  const uint8_t payload[4] = {1, 2, 3, 4};
  uint8_t buf[np::kWireBufferSize];
  EXPECT_EQ(np::encode_frame(0x7E, 1, 0, payload, 4, buf, sizeof buf), 0u);
  EXPECT_EQ(np::encode_frame(static_cast<uint8_t>(np::MsgType::Ping), 1, 0, payload, 3, buf,
                             sizeof buf),
            0u);
  EXPECT_GT(np::encode_frame(static_cast<uint8_t>(np::MsgType::Ping), 1, 0, payload, 4, buf,
                             sizeof buf),
            0u);
}

TEST(Encoder, TypedEncodeRefusesMessagesThatDoNotPack) {
  np::ParamSet empty;  // a PARAM_SET needs at least one value
  uint8_t buf[np::kWireBufferSize];
  EXPECT_EQ(np::encode(empty, 1, 0, buf, sizeof buf), 0u);
}

TEST(Encoder, OverheadIsNineBytesPerFrame) {
  np::RunStart r;  // 4-byte payload
  EXPECT_EQ(wire_of(r).size(), 4u + 9u);
}

}  // namespace
