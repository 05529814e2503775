#include <gtest/gtest.h>

#include <random>

#include "protocol/decoder.hpp"
#include "protocol/messages.hpp"
#include "test_util.hpp"

namespace np = nlsoft::protocol;
using namespace nlsoft::protocol::test;
using Kind = np::DecodeResult::Kind;

namespace {

np::Ping ping(uint32_t nonce) {
  np::Ping p;
  p.nonce = nonce;
  return p;
}

TEST(Decoder, DecodesAFrameFedOneByteAtATime) {
  const Bytes wire = wire_of(ping(0xA5A5A5A5u), 9);
  np::Decoder d;
  int frames = 0;
  for (size_t i = 0; i < wire.size(); ++i) {
    const np::DecodeResult r = d.push(wire[i]);
    if (i + 1 < wire.size()) {
      ASSERT_EQ(r.kind, Kind::None) << "byte " << i;
      continue;
    }
    ASSERT_EQ(r.kind, Kind::Frame);
    EXPECT_EQ(r.frame.header.type, static_cast<uint8_t>(np::MsgType::Ping));
    EXPECT_EQ(r.frame.header.seq, 9);
    np::Ping out;
    ASSERT_EQ(np::unpack(r.frame, out), np::StatusCode::Ok);
    EXPECT_EQ(out.nonce, 0xA5A5A5A5u);
    ++frames;
  }
  EXPECT_EQ(frames, 1);
}

TEST(Decoder, GivesTheSameEventsWhateverTheChunkSize) {
  Bytes stream;
  for (uint32_t i = 0; i < 50; ++i) {
    const Bytes w = wire_of(ping(i * 0x01010101u), static_cast<uint8_t>(i));
    stream.insert(stream.end(), w.begin(), w.end());
    if (i % 7 == 3) stream.insert(stream.end(), {0x12, 0x00});
  }
  const auto reference = decode_all(stream, 1);
  ASSERT_EQ(reference.size(), 50u + 7u);
  for (size_t chunk : {2u, 3u, 13u, 64u, 255u, 4096u}) {
    const auto events = decode_all(stream, chunk);
    ASSERT_EQ(events.size(), reference.size()) << "chunk " << chunk;
    for (size_t i = 0; i < events.size(); ++i) {
      EXPECT_EQ(events[i].kind, reference[i].kind);
      EXPECT_EQ(events[i].payload, reference[i].payload);
    }
  }
}

TEST(Decoder, FeedStopsRightAfterTheDelimiterOfEachFrame) {
  const Bytes a = wire_of(ping(1));
  Bytes stream = a;
  const Bytes b = wire_of(ping(2));
  stream.insert(stream.end(), b.begin(), b.end());
  np::Decoder d;
  np::DecodeResult r;
  EXPECT_EQ(d.feed(stream.data(), stream.size(), r), a.size());
  EXPECT_EQ(r.kind, Kind::Frame);
  EXPECT_EQ(d.feed(stream.data() + a.size(), stream.size() - a.size(), r), b.size());
  EXPECT_EQ(r.kind, Kind::Frame);
}

TEST(Decoder, AcceptsTheLargestFrameAndRejectsOneByteMoreAsOversize) {
  const Bytes payload(np::kMaxPayload, 0x5A);
  const uint8_t chunk = static_cast<uint8_t>(np::MsgType::XferChunk);
  const Bytes largest = raw_frame(1, chunk, 1, payload, chunk);
  ASSERT_EQ(largest.size(), np::kMaxRawFrame);
  const Bytes wire = wire_of_raw(largest);
  EXPECT_EQ(wire.size(), np::kMaxWireFrame);
  auto events = decode_all(wire);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Frame);

  Bytes too_big = largest;
  too_big.push_back(0x77);
  events = decode_all(wire_of_raw(too_big));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].error, np::FrameError::Oversize);
}

// Section 2: a block's implied zero counts toward the 253 bytes once the
// next code byte shows it is not the final block's (dropped) zero.
TEST(Decoder, AnImpliedZeroCountsOnlyWhenAnotherBlockFollows) {
  // 253 data bytes in one block: its implied zero is the final one, dropped.
  Bytes fits = {0xFE};
  fits.insert(fits.end(), 253, 0x11);
  fits.push_back(0);
  auto events = decode_all(fits);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NE(events[0].error, np::FrameError::Oversize);
  // The same block closed by an empty block: its zero now counts, 254 bytes.
  Bytes over = {0xFE};
  over.insert(over.end(), 253, 0x11);
  over.push_back(0x01);
  over.push_back(0);
  events = decode_all(over);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].error, np::FrameError::Oversize);
}

TEST(Decoder, RecoversOnTheFrameAfterAnOversizeRun) {
  Bytes stream(5000, 0x33);
  stream.push_back(0);
  const Bytes w = wire_of(ping(7));
  stream.insert(stream.end(), w.begin(), w.end());
  const auto events = decode_all(stream);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].error, np::FrameError::Oversize);
  EXPECT_EQ(events[1].kind, Kind::Frame);
}

TEST(Decoder, TreatsRepeatedDelimitersAsIdleNotAsErrors) {
  np::Decoder d;
  const auto events = decode_all(d, Bytes(10, 0x00));
  EXPECT_TRUE(events.empty());
  EXPECT_EQ(d.stats().empty_frames, 10u);
  EXPECT_EQ(d.stats().error_total(), 0u);
}

TEST(Decoder, ReportsEachReasonAndCountsItOnce) {
  const uint8_t p = static_cast<uint8_t>(np::MsgType::Ping);
  const Bytes good = raw_frame(1, p, 5, {1, 2, 3, 4}, p);
  struct Case {
    Bytes wire;
    np::FrameError error;
  };
  Bytes bad_crc = good;
  bad_crc[np::kHeaderSize] ^= 0xFF;  // a payload byte
  Bytes truncated = good;
  truncated.resize(truncated.size() - 1);
  Bytes longer = good;
  longer.push_back(0);
  Bytes cobs_cut = wire_of_raw(good);
  cobs_cut.erase(cobs_cut.end() - 3);
  const std::vector<Case> cases = {
      {wire_of_raw(bad_crc), np::FrameError::BadCrc},
      {wire_of_raw(truncated), np::FrameError::Truncated},
      {wire_of_raw({1, p}), np::FrameError::Truncated},
      {wire_of_raw(longer), np::FrameError::LengthMismatch},
      {wire_of_raw(raw_frame(2, p, 5, {1, 2, 3, 4}, p)), np::FrameError::WrongVersion},
      {wire_of_raw(raw_frame(1, 0x7E, 5, {1, 2, 3, 4}, 0x7E)), np::FrameError::UnknownType},
      {wire_of_raw(raw_frame(1, p, 5, {1, 2, 3, 4, 5}, p)), np::FrameError::BadLength},
      {cobs_cut, np::FrameError::CobsError},
      {{0x02, 0x00}, np::FrameError::CobsError},          // block of 1 cut by the delimiter
      {{0x02, 0x11, 0x00}, np::FrameError::WrongVersion},  // a lone byte that is not 0x01
  };
  np::Decoder d;
  uint32_t counted[np::kFrameErrorCount] = {};
  for (const Case& c : cases) {
    const auto events = decode_all(d, c.wire);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, Kind::Error);
    EXPECT_EQ(events[0].error, c.error) << np::to_string(c.error);
    ++counted[static_cast<unsigned>(events[0].error)];
  }
  for (unsigned e = 0; e < np::kFrameErrorCount; ++e) {
    EXPECT_EQ(d.stats().errors[e], counted[e]) << np::to_string(static_cast<np::FrameError>(e));
  }
  EXPECT_EQ(d.stats().frames_ok, 0u);
}

TEST(Decoder, ErrorEventsCarryTheHeaderBytesForDiagnostics) {
  const uint8_t p = static_cast<uint8_t>(np::MsgType::Ping);
  Bytes raw = raw_frame(1, p, 42, {1, 2, 3, 4}, p);
  raw.back() ^= 1;
  const auto events = decode_all(wire_of_raw(raw));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].error, np::FrameError::BadCrc);
  EXPECT_EQ(events[0].header.type, p);
  EXPECT_EQ(events[0].header.seq, 42);
}

TEST(Decoder, GarbageCostsAtMostTheFrameItLandsIn) {
  std::mt19937 rng(99);
  for (int trial = 0; trial < 500; ++trial) {
    Bytes stream = wire_of(ping(1), 1);
    Bytes garbage(1 + rng() % 40);
    for (auto& b : garbage) b = static_cast<uint8_t>(rng());
    stream.insert(stream.end(), garbage.begin(), garbage.end());
    stream.push_back(0);  // the garbage ends somewhere; the next frame starts clean
    const Bytes next = wire_of(ping(2), 2);
    stream.insert(stream.end(), next.begin(), next.end());
    const auto events = decode_all(stream, 1 + rng() % 16);
    ASSERT_GE(events.size(), 2u);
    EXPECT_EQ(events.front().kind, Kind::Frame);
    EXPECT_EQ(events.back().kind, Kind::Frame);
    EXPECT_EQ(events.back().header.seq, 2);
  }
}

TEST(Decoder, ResetDropsAPartialFrame) {
  const Bytes w = wire_of(ping(5));
  np::Decoder d;
  np::DecodeResult r;
  d.feed(w.data(), 6, r);
  EXPECT_EQ(r.kind, Kind::None);
  d.reset();
  const auto events = decode_all(d, w);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Frame);
  EXPECT_EQ(d.stats().error_total(), 0u);
}

TEST(Decoder, CountsEveryByteItIsGiven) {
  np::Decoder d;
  Bytes stream = wire_of(ping(5));
  stream.insert(stream.end(), {1, 2, 3, 0, 0});
  decode_all(d, stream, 5);
  d.push(0x10);
  EXPECT_EQ(d.stats().bytes, stream.size() + 1);
  EXPECT_EQ(d.stats().frames_ok, 1u);
  EXPECT_EQ(d.stats().error_total(), 1u);
  EXPECT_EQ(d.stats().empty_frames, 1u);
}

}  // namespace
