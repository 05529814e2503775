// Session against a fake firmware on a pty: retries keep the seq, timeouts
// say what failed, NACKs arrive in words, a reply racing its timeout is
// taken exactly once, duplicate and stale replies are ignored.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <chrono>
#include <thread>

#include "app/link/link_error.hpp"
#include "app/link/param_catalog.hpp"
#include "app/link/session.hpp"
#include "fake_peer.hpp"

namespace nlsoft::console {
namespace {

namespace p = nlsoft::protocol;
using test::FakePeer;
using namespace std::chrono_literals;

SessionOptions fast_options() {
  SessionOptions o;
  o.timeout = 60ms;
  o.tries = 3;
  o.keepalive = 0ms;  // tests count every request
  o.silence_limit = 10s;
  return o;
}

void pong(FakePeer& peer, const p::FrameView& f) {
  p::Ping ping;
  ASSERT_EQ(p::unpack(f, ping), p::StatusCode::Ok);
  p::Pong reply;
  reply.nonce = ping.nonce;
  reply.uptime_ms = 7;
  peer.reply(reply, f.header.seq);
}

p::Pong ping(Session& s, uint32_t nonce) {
  p::Ping req;
  req.nonce = nonce;
  return s.call<p::Pong>(req);
}

TEST(Session, ReplyMatchedBySequence) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) { pong(pe, f); });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  for (uint32_t i = 1; i <= 5; ++i) EXPECT_EQ(ping(s, i).nonce, i);
  const auto seqs = peer.seqs_seen();
  ASSERT_EQ(seqs.size(), 5u);
  for (size_t i = 1; i < seqs.size(); ++i) EXPECT_EQ(uint8_t(seqs[i - 1] + 1), seqs[i]) << "a new seq per request";
  EXPECT_EQ(s.stats().retransmits, 0u);
}

TEST(Session, RetriesWithTheSameSequence) {
  std::atomic<int> seen{0};
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (++seen <= 2) return;  // the first two copies are "lost"
    pong(pe, f);
  });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  EXPECT_EQ(ping(s, 42).nonce, 42u);
  const auto seqs = peer.seqs_seen();
  ASSERT_EQ(seqs.size(), 3u);
  EXPECT_EQ(seqs[0], seqs[1]);
  EXPECT_EQ(seqs[1], seqs[2]);
  EXPECT_EQ(s.stats().retransmits, 2u);
}

TEST(Session, TimeoutSaysWhatFailedAfterHowManyTries) {
  FakePeer peer([](FakePeer&, const p::FrameView&) {});
  Session s(fast_options());
  s.open(peer.path(), 115200);
  p::ParamSet req;
  req.id = 0;
  req.count = 1;
  try {
    s.call<p::ParamValue>(req);
    FAIL() << "expected a LinkError";
  } catch (const LinkError& e) {
    EXPECT_STREQ(e.what(), "no reply to PARAM_SET after 3 tries (180 ms)");
  }
  EXPECT_EQ(peer.requests_seen(), 3);
  EXPECT_EQ(s.stats().timeouts, 1u);
}

TEST(Session, NackBecomesTypedErrorInWords) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) {
    p::Nack n;
    n.request_type = f.header.type;
    n.status = uint8_t(p::StatusCode::OutOfRange);
    n.field = 1;
    n.element = 1;
    pe.reply(n, f.header.seq);
  });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  p::ParamSet req;
  req.id = 0;
  req.count = 3;
  try {
    s.call<p::ParamValue>(req);
    FAIL() << "expected a NackError";
  } catch (const NackError& e) {
    EXPECT_EQ(e.status(), p::StatusCode::OutOfRange);
    EXPECT_EQ(e.nack.element, 1);
    EXPECT_STREQ(e.what(), "PARAM_SET refused: out of range (values[1])");
  }
}

TEST(Session, ParamRefusalNamesElementAndRange) {
  ParamInfo q;
  q.name = "Q";
  q.size = 3;
  q.min = 0;
  q.max = 1e12f;
  p::Nack n;
  n.request_type = uint8_t(p::MsgType::ParamSet);
  n.status = uint8_t(p::StatusCode::OutOfRange);
  n.field = 1;
  n.element = 1;
  EXPECT_EQ(describe_param_refusal(q, n, {1e6, -2, 1e6}), "Q[1] = -2 is out of range [0, 1e+12]");
  n.status = uint8_t(p::StatusCode::WrongState);
  EXPECT_EQ(describe_param_refusal(q, n, {1, 2, 3}), "Q can only change while no run is active");
  EXPECT_EQ(request_field_name(uint8_t(p::MsgType::RefSelect), 8), "lambda");
  EXPECT_EQ(status_words(200), "failed (status 200)");
}

TEST(Session, ReplyRacingItsTimeoutIsTakenExactlyOnce) {
  // The first copy of each request is answered about one timeout late, so
  // the reply and the retransmission cross; the retransmission is then
  // answered at once, as the firmware does from its reply cache. Each call
  // must get its own nonce back, once, whichever copy wins.
  std::atomic<int> n{0};
  std::atomic<int> last_seq{-1};
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (last_seq.exchange(f.header.seq) != f.header.seq)
      std::this_thread::sleep_for(std::chrono::microseconds(n++ % 2 ? 59000 : 61000));
    pong(pe, f);
  });
  SessionOptions o = fast_options();
  o.tries = 4;
  Session s(o);
  s.open(peer.path(), 115200);
  for (uint32_t i = 100; i < 115; ++i) EXPECT_EQ(ping(s, i).nonce, i);
}

TEST(Session, DuplicateRepliesAreIgnored) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) {
    pong(pe, f);
    pong(pe, f);  // as if the firmware answered a retransmission from its cache
  });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  for (uint32_t i = 1; i <= 10; ++i) EXPECT_EQ(ping(s, i).nonce, i);
  // Wait for the last duplicate to be read.
  for (int i = 0; i < 100 && s.stats().stale_replies < 10; ++i) std::this_thread::sleep_for(5ms);
  EXPECT_EQ(s.stats().stale_replies, 10u);
}

TEST(Session, StaleSequenceAndWrongTypeAreNotTakenAsTheReply) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) {
    p::Pong wrong_seq;
    wrong_seq.nonce = 999;
    pe.reply(wrong_seq, uint8_t(f.header.seq + 7));
    p::Ack wrong_type;  // an ACK for another request type
    wrong_type.request_type = uint8_t(p::MsgType::RunStop);
    pe.reply(wrong_type, f.header.seq);
    pong(pe, f);
  });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  EXPECT_EQ(ping(s, 5).nonce, 5u);
}

TEST(Session, TelemetryBetweenRequestAndReplyAndLostFrames) {
  std::atomic<uint32_t> lost_sum{0};
  std::atomic<int> frames{0};
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) {
    p::Telemetry t;
    t.mask = p::telemetry_field::kStep;
    t.n = 1;
    t.m = 1;
    for (uint16_t seq : {uint16_t(10), uint16_t(11), uint16_t(14), uint16_t(15)}) {  // 12 and 13 never arrive
      t.tseq = seq;
      t.step = seq;
      pe.send_unsolicited(t);
    }
    pong(pe, f);
  });
  Session s(fast_options());
  s.on_telemetry([&](const p::Telemetry&, uint32_t lost) {
    lost_sum += lost;
    ++frames;
  });
  s.open(peer.path(), 115200);
  EXPECT_EQ(ping(s, 1).nonce, 1u);
  EXPECT_EQ(frames.load(), 4);
  EXPECT_EQ(lost_sum.load(), 2u);
  EXPECT_EQ(s.stats().lost_telemetry, 2u);
  EXPECT_EQ(s.stats().telemetry_frames, 4u);
}

TEST(Session, CorruptBytesAreCountedAndTheNextFrameStillDecodes) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) {
    uint8_t buf[p::kWireBufferSize];
    p::Pong reply;
    reply.nonce = 77;
    size_t n = p::encode_reply(reply, f.header.seq, buf, sizeof buf);
    buf[3] ^= 0x40;  // flip a bit: bad CRC
    pe.write(buf, n);
    n = p::encode_reply(reply, f.header.seq, buf, sizeof buf);
    pe.write(buf, n);
  });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  EXPECT_EQ(ping(s, 77).nonce, 77u);
  const LinkStats st = s.stats();
  EXPECT_EQ(st.crc_errors + st.decode_errors, 1u);
}

TEST(Session, LostPortIsReportedAndReopenedWhenItReturns) {
  std::mutex mu;
  std::vector<LinkEvent::Kind> events;
  auto seen = [&](LinkEvent::Kind k) {
    std::lock_guard<std::mutex> lock(mu);
    return std::find(events.begin(), events.end(), k) != events.end();
  };
  auto wait_for = [&](LinkEvent::Kind k) {
    for (int i = 0; i < 300 && !seen(k); ++i) std::this_thread::sleep_for(10ms);
    return seen(k);
  };
  auto peer = std::make_unique<FakePeer>([](FakePeer& pe, const p::FrameView& f) { pong(pe, f); });
  const std::string path = peer->path();
  SessionOptions o = fast_options();
  o.reconnect_interval = 20ms;
  Session s(o);
  s.on_event([&](const LinkEvent& e) {
    std::lock_guard<std::mutex> lock(mu);
    events.push_back(e.kind);
  });
  s.open(path, 115200);
  EXPECT_EQ(ping(s, 1).nonce, 1u);

  peer.reset();  // the cable is pulled: the pty disappears
  ASSERT_TRUE(wait_for(LinkEvent::Kind::Down));
  EXPECT_FALSE(s.connected());
  try {
    ping(s, 2);
    FAIL() << "a request on a dead link must fail";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("is down, reconnecting"), std::string::npos) << e.what();
  }

  peer = std::make_unique<FakePeer>([](FakePeer& pe, const p::FrameView& f) { pong(pe, f); });
  if (peer->path() != path) GTEST_SKIP() << "the kernel gave the new pty another name; cannot test the reopen";
  ASSERT_TRUE(wait_for(LinkEvent::Kind::Up));
  EXPECT_TRUE(s.connected());
  EXPECT_EQ(ping(s, 3).nonce, 3u);
  EXPECT_EQ(s.stats().reconnects, 1u);
}

TEST(Session, MissingPortIsAClearError) {
  Session s(fast_options());
  try {
    s.open("/dev/does-not-exist-nlsoft", 115200);
    FAIL();
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open /dev/does-not-exist-nlsoft"), std::string::npos) << e.what();
  }
}

TEST(Session, NonStandardBaudIsAccepted) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) { pong(pe, f); });
  Session s(fast_options());
  s.open(peer.path(), 250000);
  EXPECT_EQ(ping(s, 3).nonce, 3u);
}

}  // namespace
}  // namespace nlsoft::console
