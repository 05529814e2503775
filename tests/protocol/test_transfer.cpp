#include <gtest/gtest.h>

#include <vector>

#include "protocol/crc.hpp"
#include "protocol/reply_cache.hpp"
#include "protocol/transfer.hpp"

namespace np = nlsoft::protocol;

namespace {

constexpr uint8_t kKind = static_cast<uint8_t>(np::XferKind::RefTable);

struct Upload {
  std::vector<uint8_t> object;
  np::XferBegin begin;

  explicit Upload(size_t size) : object(size) {
    for (size_t i = 0; i < size; ++i) object[i] = static_cast<uint8_t>(i * 7 + 3);
    begin.kind = kKind;
    begin.total_size = static_cast<uint32_t>(size);
    begin.crc32 = np::crc32(object.data(), object.size());
  }

  np::XferChunk chunk(uint32_t offset, uint8_t size) const {
    np::XferChunk c;
    c.kind = kKind;
    c.offset = offset;
    c.size = size;
    for (uint8_t i = 0; i < size; ++i) c.data[i] = object[offset + i];
    return c;
  }
};

TEST(Transfer, ChunksInOrderThenCommitDeliverTheObject) {
  Upload up(1000);
  std::vector<uint8_t> stage(2048);
  np::TransferReceiver rx(kKind, stage.data(), stage.size());
  ASSERT_EQ(rx.begin(up.begin).status, np::StatusCode::Ok);
  uint32_t next = 0;
  while (next < 1000) {
    const auto size = static_cast<uint8_t>(std::min<uint32_t>(241, 1000 - next));
    const np::XferReply r = rx.chunk(up.chunk(next, size));
    ASSERT_EQ(r.status, np::StatusCode::Ok);
    ASSERT_EQ(r.ack.next_offset, next + size);
    next = r.ack.next_offset;
  }
  EXPECT_EQ(rx.commit().status, np::StatusCode::Ok);
  EXPECT_EQ(std::vector<uint8_t>(rx.data(), rx.data() + rx.size()), up.object);
}

TEST(Transfer, LostChunkIsHealedByTheAckedNextOffset) {
  Upload up(600);
  std::vector<uint8_t> stage(600);
  np::TransferReceiver rx(kKind, stage.data(), stage.size());
  rx.begin(up.begin);
  EXPECT_EQ(rx.chunk(up.chunk(0, 200)).ack.next_offset, 200u);
  // The chunk at 200 is lost; the one at 400 is ignored and the ack says 200.
  EXPECT_EQ(rx.chunk(up.chunk(400, 200)).ack.next_offset, 200u);
  EXPECT_EQ(rx.chunk(up.chunk(200, 200)).ack.next_offset, 400u);
  // A duplicate (its ack was lost) changes nothing.
  EXPECT_EQ(rx.chunk(up.chunk(200, 200)).ack.next_offset, 400u);
  EXPECT_EQ(rx.chunk(up.chunk(400, 200)).ack.next_offset, 600u);
  EXPECT_EQ(rx.commit().status, np::StatusCode::Ok);
}

TEST(Transfer, BeginWithTheSameObjectResumesAndRestartStartsOver) {
  Upload up(500);
  std::vector<uint8_t> stage(500);
  np::TransferReceiver rx(kKind, stage.data(), stage.size());
  rx.begin(up.begin);
  rx.chunk(up.chunk(0, 241));
  EXPECT_EQ(rx.begin(up.begin).ack.next_offset, 241u);
  np::XferBegin restart = up.begin;
  restart.options = np::xfer_options::kRestart;
  EXPECT_EQ(rx.begin(restart).ack.next_offset, 0u);
  rx.chunk(up.chunk(0, 241));
  np::XferBegin other = up.begin;
  other.crc32 ^= 1;
  EXPECT_EQ(rx.begin(other).ack.next_offset, 0u);  // a different object: fresh start
}

TEST(Transfer, CommitRefusesIncompleteKeepsItOpenAndDiscardsOnBadChecksum) {
  Upload up(300);
  std::vector<uint8_t> stage(300);
  np::TransferReceiver rx(kKind, stage.data(), stage.size());
  np::XferBegin wrong_crc = up.begin;
  wrong_crc.crc32 ^= 0x80000000u;
  rx.begin(wrong_crc);
  rx.chunk(up.chunk(0, 200));
  EXPECT_EQ(rx.commit().status, np::StatusCode::XferIncomplete);
  EXPECT_TRUE(rx.is_open());
  rx.chunk(up.chunk(200, 100));
  EXPECT_EQ(rx.commit().status, np::StatusCode::BadChecksum);
  EXPECT_FALSE(rx.is_open());
  EXPECT_EQ(rx.commit().status, np::StatusCode::XferNotOpen);
}

TEST(Transfer, RejectsSizesAndChunksOutsideTheObject) {
  Upload up(100);
  std::vector<uint8_t> stage(100);
  np::TransferReceiver rx(kKind, stage.data(), stage.size());
  EXPECT_EQ(rx.chunk(up.chunk(0, 10)).status, np::StatusCode::XferNotOpen);
  np::XferBegin big = up.begin;
  big.total_size = 101;
  const np::XferReply too_large = rx.begin(big);
  EXPECT_EQ(too_large.status, np::StatusCode::TooLarge);
  EXPECT_EQ(too_large.field, 2);
  np::XferBegin empty = up.begin;
  empty.total_size = 0;
  EXPECT_EQ(rx.begin(empty).status, np::StatusCode::OutOfRange);
  rx.begin(up.begin);
  np::XferChunk past = up.chunk(0, 10);
  past.offset = 95;
  const np::XferReply r = rx.chunk(past);
  EXPECT_EQ(r.status, np::StatusCode::OutOfRange);
  EXPECT_EQ(r.field, 1);
  past.offset = 0xFFFFFFFFu;  // no wrap-around
  EXPECT_EQ(rx.chunk(past).status, np::StatusCode::OutOfRange);
}

TEST(ReplyCache, RepeatsTheStoredReplyOnlyForTheSameSeqTypeAndPayload) {
  np::ReplyCache cache;
  const uint8_t run7[] = {7, 0, 0, 0};
  np::FrameView req;
  req.header.seq = 9;
  req.header.type = static_cast<uint8_t>(np::MsgType::RunStart);
  req.header.length = sizeof run7;
  req.payload = run7;
  const uint8_t* wire = nullptr;
  size_t n = 0;
  EXPECT_FALSE(cache.find(req, wire, n));
  const uint8_t reply[] = {3, 1, 0x40, 9, 1, 0};
  cache.store(req, reply, sizeof reply);
  ASSERT_TRUE(cache.find(req, wire, n));
  EXPECT_EQ(std::vector<uint8_t>(wire, wire + n), std::vector<uint8_t>(reply, reply + 6));
  np::FrameView next = req;
  next.header.seq = 10;
  EXPECT_FALSE(cache.find(next, wire, n));
  np::FrameView other = req;
  other.header.type = static_cast<uint8_t>(np::MsgType::XferCommit);
  EXPECT_FALSE(cache.find(other, wire, n));
  // A restarted console reusing seq 9 for another run: executed, not the old reply.
  const uint8_t run8[] = {8, 0, 0, 0};
  np::FrameView reused = req;
  reused.payload = run8;
  EXPECT_FALSE(cache.find(reused, wire, n));
}

}  // namespace
