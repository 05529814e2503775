// Session against a fake firmware on a pty: retries keep the seq, timeouts
// say what failed, NACKs arrive in words, a reply racing its timeout is
// taken exactly once, duplicate and stale replies are ignored, a lost port
// is reopened and whatever answers there must be the device it was before.
#include <gtest/gtest.h>

#include <random>

#include <algorithm>
#include <cmath>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "app/link/device.hpp"
#include "app/link/link_error.hpp"
#include "app/link/param_catalog.hpp"
#include "app/link/session.hpp"
#include "app/support/fake_peer.hpp"
#include "app/support/temp_dir.hpp"

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

// A PING frame as it goes on the wire, for the raw exchange.
std::vector<uint8_t> ping_wire(uint32_t nonce, uint8_t seq) {
  p::Ping ping;
  ping.nonce = nonce;
  uint8_t buf[p::kWireBufferSize];
  const size_t n = p::encode(ping, seq, 0, buf, sizeof buf);
  return std::vector<uint8_t>(buf, buf + n);
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
  // Spare tries: on a loaded machine the answer to the third copy may come
  // after a fourth went out; every copy must still carry the same seq.
  SessionOptions o = fast_options();
  o.tries = 8;
  Session s(o);
  s.open(peer.path(), 115200);
  EXPECT_EQ(ping(s, 42).nonce, 42u);
  const auto seqs = peer.seqs_seen();
  ASSERT_GE(seqs.size(), 3u);
  for (size_t i = 1; i < seqs.size(); ++i) EXPECT_EQ(seqs[i], seqs[0]) << "copy " << i;
  EXPECT_EQ(s.stats().retransmits, seqs.size() - 1);
}

// The error a PARAM_SET that gets no reply ends with.
std::string unanswered_param_set(Session& s) {
  p::ParamSet req;
  req.id = 0;
  req.count = 1;
  try {
    s.call<p::ParamValue>(req);
  } catch (const LinkError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a LinkError";
  return "";
}

// The message gives the tries, the timeout of each and the time waited in
// all, which is what it took: never less than the tries' timeouts, never
// more than the caller saw pass.
TEST(Session, TimeoutSaysWhatFailedAfterHowManyTries) {
  FakePeer peer([](FakePeer&, const p::FrameView&) {});
  Session s(fast_options());
  s.open(peer.path(), 115200);
  const auto began = std::chrono::steady_clock::now();
  const std::string why = unanswered_param_set(s);
  const auto seen_ms = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - began);
  const std::string head = "no reply to PARAM_SET after 3 tries, 60 ms each (";
  ASSERT_EQ(why.rfind(head, 0), 0u) << why;
  const long waited_ms = std::stol(why.substr(head.size()));
  EXPECT_GE(waited_ms, 180) << why;
  EXPECT_LE(waited_ms, seen_ms.count()) << why;
  const std::string tail = " ms in all); nothing arrived from " + peer.path() +
                           ": is the firmware running? (a slow device needs a longer --timeout)";
  EXPECT_EQ(why.substr(why.size() - std::min(why.size(), tail.size())), tail) << why;
  EXPECT_EQ(peer.requests_seen(), 3);
  EXPECT_EQ(s.stats().timeouts, 1u);
}

// A silent line is reported silent; closing the session ends the silence
// without a frame, which is not "frames arriving again".
TEST(Session, ClosingASilentLinkIsNotTakenForFramesArriving) {
  FakePeer peer([](FakePeer&, const p::FrameView&) {});
  SessionOptions o = fast_options();
  o.silence_limit = 200ms;
  Session s(o);
  std::mutex mu;
  std::vector<LinkEvent::Kind> kinds;
  s.on_event([&](const LinkEvent& e) {
    std::lock_guard<std::mutex> lock(mu);
    kinds.push_back(e.kind);
  });
  s.open(peer.path(), 115200);
  for (int i = 0; i < 300; ++i) {
    {
      std::lock_guard<std::mutex> lock(mu);
      if (!kinds.empty()) break;
    }
    std::this_thread::sleep_for(10ms);
  }
  s.close();
  std::lock_guard<std::mutex> lock(mu);
  ASSERT_FALSE(kinds.empty()) << "the silence was reported";
  EXPECT_EQ(kinds[0], LinkEvent::Kind::Silent);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), LinkEvent::Kind::Resumed), 0) << "no frame ever came";
}

// A line that gives back what is written (a loopback plug, a device that
// echoes): the frames that arrive are the console's own requests, named as
// such rather than taken for a firmware that does not answer.
TEST(Session, AnEchoingLineIsNamedAsSuch) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) {
    uint8_t wire[p::kWireBufferSize];
    const size_t n = p::encode_frame(f.header.type, f.header.seq, f.header.flags, f.payload, f.header.length, wire,
                                     sizeof wire);
    pe.write(wire, n);
  });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  const std::string why = unanswered_param_set(s);
  EXPECT_NE(why.find("the console's own frames came back from " + peer.path() + " (3 of them) and nothing else: the "
                     "line echoes what is sent"),
            std::string::npos)
      << why;
  EXPECT_EQ(why.find("nothing arrived"), std::string::npos) << why;
  EXPECT_EQ(why.find("none of them a valid frame"), std::string::npos) << why;
  EXPECT_EQ(s.stats().echoed_frames, 3u);
}

// Line noise (another baud rate, another device) answers with bytes that are
// no frame; the error says so, and does not take the noise for a firmware of
// another protocol version (its version byte is read before the CRC).
TEST(Session, NoiseIsReportedAsNoFrameNotAsAnotherProtocol) {
  std::mt19937 rng(7);
  FakePeer peer([&rng](FakePeer& pe, const p::FrameView&) {
    uint8_t noise[600];
    for (uint8_t& b : noise) b = uint8_t(rng());
    pe.write(noise, sizeof noise);
  });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  const std::string why = unanswered_param_set(s);
  EXPECT_NE(why.find("no reply to PARAM_SET after 3 tries"), std::string::npos) << why;
  EXPECT_NE(why.find("bytes arrived from " + peer.path() + ", none of them a valid frame"), std::string::npos) << why;
  EXPECT_EQ(why.find("protocol v"), std::string::npos) << why;
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
  // A value a double holds but a float32 does not arrives as infinity: the
  // refusal says it overflowed, and the limit.
  n.status = uint8_t(p::StatusCode::NotFinite);
  n.element = 0;
  EXPECT_EQ(describe_param_refusal(q, n, {1e40, 1, 1}),
            "Q[0] = 1e+40 overflows a float32 (the firmware's number type): its magnitude must be at most 3.40282e+38");
  EXPECT_EQ(describe_param_refusal(q, n, {std::nan(""), 1, 1}), "Q[0] must be a finite number");
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
  // Only the first request's reply is damaged: under load the session may
  // send the ping again, and that retry must not add a second error.
  std::atomic<bool> damaged{false};
  FakePeer peer([&damaged](FakePeer& pe, const p::FrameView& f) {
    uint8_t buf[p::kWireBufferSize];
    p::Pong reply;
    reply.nonce = 77;
    size_t n = p::encode_reply(reply, f.header.seq, buf, sizeof buf);
    if (!damaged.exchange(true)) {
      // The version byte, always 1 and always wire byte 1 (right after the
      // first COBS code byte): flipping it can neither make a delimiter nor
      // move a code byte. The seq byte, random per session, could do both
      // (a seq of 0x40 flipped to 0x00 splits the frame into two errors).
      ASSERT_EQ(buf[1], p::kProtocolVersion);
      buf[1] ^= 0x40;
      pe.write(buf, n);
    }
    n = p::encode_reply(reply, f.header.seq, buf, sizeof buf);
    pe.write(buf, n);
  });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  EXPECT_EQ(ping(s, 77).nonce, 77u);
  const LinkStats st = s.stats();
  EXPECT_EQ(st.crc_errors + st.decode_errors, 1u);
}

// Link events as the supervisor thread reports them.
class Events {
 public:
  Session::EventHandler handler() {
    return [this](const LinkEvent& e) {
      {
        std::lock_guard<std::mutex> lock(mu_);
        events_.push_back(e);
      }
      cv_.notify_all();
    };
  }
  bool wait_for(const std::function<bool(const LinkEvent&)>& match) {
    std::unique_lock<std::mutex> lock(mu_);
    return cv_.wait_for(lock, 3s, [&] { return std::any_of(events_.begin(), events_.end(), match); });
  }
  bool wait_for(LinkEvent::Kind k) {
    return wait_for([k](const LinkEvent& e) { return e.kind == k; });
  }
  int count(LinkEvent::Kind k) {
    std::lock_guard<std::mutex> lock(mu_);
    return int(std::count_if(events_.begin(), events_.end(), [k](const LinkEvent& e) { return e.kind == k; }));
  }
  std::string all() {
    std::lock_guard<std::mutex> lock(mu_);
    std::string out;
    for (const LinkEvent& e : events_) out += std::string(link_event_name(e.kind)) + ": " + e.detail + "\n";
    return out;
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  std::vector<LinkEvent> events_;
};

// A port name only this test uses: a symlink to the fake peer's pty, the way
// udev's /dev/serial/by-id/ names point at a board's tty. Reconnecting by the
// pty's own name is not private: the kernel gives a freed /dev/pts/N to the
// next pty opened anywhere (lowest free number), so under `ctest -j` another
// test's pty could answer there. Behind this link only the test decides what
// is plugged in.
struct PrivatePort {
  test::TempDir dir;
  std::string path = dir.file("port");
  void plug(const FakePeer& peer) { std::filesystem::create_symlink(peer.path(), path); }
  void unplug() { std::filesystem::remove(path); }
};

p::Info board_info(p::Platform platform, const char* firmware, uint8_t major) {
  p::Info info;
  info.platform = uint8_t(platform);
  info.m = 2;
  info.n = 2;
  info.w = 2;
  info.nd = 2;
  info.dd = 2;
  info.max_n = 50;
  info.max_nc = 10;
  info.fw_major = major;
  info.loop_rate_hz = 100;
  std::snprintf(info.firmware, sizeof info.firmware, "%s", firmware);
  return info;
}

// A firmware that answers INFO_GET with `info` and PING with `uptime_ms`;
// `pings` counts the PINGs it answered.
FakePeer::Handler board(const p::Info& info, uint32_t uptime_ms, std::atomic<int>* pings = nullptr) {
  return [info, uptime_ms, pings](FakePeer& pe, const p::FrameView& f) {
    if (f.header.type == uint8_t(p::MsgType::InfoGet)) return pe.reply(info, f.header.seq);
    p::Ping req;
    if (p::unpack(f, req) != p::StatusCode::Ok) return;
    if (pings) ++*pings;
    p::Pong reply;
    reply.nonce = req.nonce;
    reply.uptime_ms = uptime_ms;
    pe.reply(reply, f.header.seq);
  };
}

TEST(Session, LostPortIsReportedAndReopenedWhenItReturns) {
  const p::Info hasel = board_info(p::Platform::Hasel, "nlsoft-fake", 1);
  PrivatePort port;
  auto peer = std::make_unique<FakePeer>(board(hasel, 5000));
  port.plug(*peer);
  SessionOptions o = fast_options();
  o.reconnect_interval = 20ms;
  Events events;
  Session s(o);
  s.on_event(events.handler());
  s.open(port.path, 115200);
  EXPECT_STREQ(s.call<p::Info>(p::InfoGet{}).firmware, "nlsoft-fake");
  EXPECT_EQ(ping(s, 1).nonce, 1u);

  port.unplug();  // the cable is pulled: the port's name and its pty disappear
  peer.reset();
  ASSERT_TRUE(events.wait_for(LinkEvent::Kind::Down)) << events.all();
  EXPECT_FALSE(s.connected());
  try {
    ping(s, 2);
    FAIL() << "a request on a dead link must fail";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("is down, reconnecting"), std::string::npos) << e.what();
  }

  // The same board comes back after a reset: same identity, uptime restarted.
  peer = std::make_unique<FakePeer>(board(hasel, 3));
  port.plug(*peer);
  ASSERT_TRUE(events.wait_for(LinkEvent::Kind::Up)) << events.all();
  EXPECT_TRUE(s.connected());
  EXPECT_EQ(ping(s, 3).uptime_ms, 3u);
  EXPECT_EQ(s.stats().reconnects, 1u);
}

// A pty opened by its own /dev/pts/N whose other end closed never comes
// back: the number goes to the next pty anyone opens, so the session says
// so and does not reopen it.
TEST(Session, AHungUpPtyIsNotReopened) {
  const p::Info hasel = board_info(p::Platform::Hasel, "nlsoft-fake", 1);
  auto peer = std::make_unique<FakePeer>(board(hasel, 5000));
  ASSERT_EQ(peer->path().rfind("/dev/pts/", 0), 0u);
  SessionOptions o = fast_options();
  o.reconnect_interval = 20ms;
  Events events;
  Session s(o);
  s.on_event(events.handler());
  s.open(peer->path(), 115200);
  EXPECT_EQ(ping(s, 1).nonce, 1u);
  EXPECT_TRUE(s.will_reopen());
  peer.reset();
  ASSERT_TRUE(events.wait_for(LinkEvent::Kind::Down)) << events.all();
  EXPECT_NE(events.all().find("a pseudo-terminal does not come back"), std::string::npos) << events.all();
  EXPECT_FALSE(s.will_reopen());
  try {
    ping(s, 2);
    FAIL() << "a request on a dead link must fail";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("is down for good"), std::string::npos) << e.what();
  }
}

// The console's simulator restart closes the session and opens it on the
// new simulator's pty. An event the old link posted that the supervisor had
// not passed on when close() returned belongs to the closed link: the next
// open() must not deliver it as if the new port had said it (stress run 8 at
// e03a5ca: the dead pty's "End of file ... (reconnecting)" came after, and
// replaced, "simulator restarted on"). The handler holds the supervisor on
// the first event so that the old link's Down is still queued when close()
// stops it.
TEST(Session, AnEventOfAClosedLinkIsNotDeliveredAfterTheNextOpen) {
  const p::Info hasel = board_info(p::Platform::Hasel, "nlsoft-fake", 1);
  auto old_sim = std::make_unique<FakePeer>(board(hasel, 5000));
  FakePeer new_sim(board(hasel, 3));
  const std::string old_port = old_sim->path();
  SessionOptions o = fast_options();
  o.silence_limit = 200ms;  // the first event: the old link is silent
  Session s(o);
  std::mutex mu;
  std::condition_variable cv;
  bool holding = false, release = false, reopened = false;
  std::vector<LinkEvent> after_open;
  s.on_event([&](const LinkEvent& e) {
    std::unique_lock<std::mutex> lock(mu);
    if (reopened) after_open.push_back(e);
    if (holding) return;
    holding = true;
    cv.notify_all();
    cv.wait(lock, [&] { return release; });
  });
  s.open(old_port, 115200);
  {
    std::unique_lock<std::mutex> lock(mu);
    ASSERT_TRUE(cv.wait_for(lock, 5s, [&] { return holding; })) << "the silence was not reported";
  }
  old_sim.reset();  // the old simulator dies: its link posts Down
  for (int i = 0; i < 300 && s.connected(); ++i) std::this_thread::sleep_for(10ms);
  ASSERT_FALSE(s.connected()) << "the old link did not go down";
  std::this_thread::sleep_for(100ms);  // Down is posted just after `connected` drops
  std::thread closer([&] { s.close(); });
  std::this_thread::sleep_for(300ms);  // close() has asked the supervisor to stop
  {
    std::lock_guard<std::mutex> lock(mu);
    release = true;
  }
  cv.notify_all();
  closer.join();
  {
    std::lock_guard<std::mutex> lock(mu);
    reopened = true;
  }
  s.open(new_sim.path(), 115200);
  EXPECT_EQ(ping(s, 2).uptime_ms, 3u);
  std::this_thread::sleep_for(300ms);  // three supervisor rounds on the new link
  s.close();
  std::lock_guard<std::mutex> lock(mu);
  // The new link may report its own silence; it never went down.
  for (const LinkEvent& e : after_open)
    if (e.kind == LinkEvent::Kind::Down || e.detail.find(old_port) != std::string::npos)
      ADD_FAILURE() << "delivered after the reopen: " << link_event_name(e.kind) << ": " << e.detail;
}

TEST(Session, AnotherDeviceOnTheSamePortIsRefusedOnReconnect) {
  PrivatePort port;
  auto peer = std::make_unique<FakePeer>(board(board_info(p::Platform::Hasel, "nlsoft-fake", 1), 5000));
  port.plug(*peer);
  SessionOptions o = fast_options();
  o.reconnect_interval = 20ms;
  Events events;
  Session s(o);
  s.on_event(events.handler());
  s.open(port.path, 115200);
  EXPECT_STREQ(s.call<p::Info>(p::InfoGet{}).firmware, "nlsoft-fake");

  port.unplug();
  peer.reset();
  ASSERT_TRUE(events.wait_for(LinkEvent::Kind::Down)) << events.all();

  // Another board, of another rig and firmware, now gets the same name.
  std::atomic<int> pings{0};
  auto other = std::make_unique<FakePeer>(board(board_info(p::Platform::Tendon, "other-fw", 2), 7, &pings));
  port.plug(*other);
  const std::string refusal = "a different device now answers at " + port.path +
                              ": platform tendon (was hasel); firmware other-fw 2.0.0 (was nlsoft-fake 1.0.0)";
  ASSERT_TRUE(events.wait_for([&](const LinkEvent& e) { return e.detail == refusal; })) << events.all();
  EXPECT_FALSE(s.connected());
  try {
    ping(s, 4);
    FAIL() << "a request must not go to another device";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find(refusal), std::string::npos) << e.what();
  }
  EXPECT_EQ(pings.load(), 0) << "nothing but INFO_GET may reach the other device";
  EXPECT_EQ(events.count(LinkEvent::Kind::Up), 0) << events.all();
  EXPECT_EQ(s.stats().reconnects, 0u);
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

namespace nlsoft::console {
namespace {

// Protocol 1.1, section 3: each session starts at a random seq, so a
// restarted console rarely meets the firmware's memory of its last request.
TEST(Session, EachSessionStartsAtARandomSequenceNumber) {
  std::vector<uint8_t> first;
  for (int i = 0; i < 6; ++i) {
    FakePeer peer([](FakePeer& pe, const p::FrameView& f) { pong(pe, f); });
    Session s(fast_options());
    s.open(peer.path(), 115200);
    ping(s, 1);
    ASSERT_FALSE(peer.seqs_seen().empty());
    first.push_back(peer.seqs_seen().front());
  }
  std::sort(first.begin(), first.end());
  EXPECT_GT(std::unique(first.begin(), first.end()) - first.begin(), 1) << "six sessions, one first seq";
}

// INFO_GET is answered by INFO_EX (1.1) or INFO (1.0); both read as INFO,
// and the limits are known only from INFO_EX. A refused upload names the limit.
TEST(Session, InfoExAndInfoBothAnswerInfoGetAndTheLimitIsShown) {
  const p::Info info = board_info(p::Platform::Hasel, "nlsoft-fake", 1);
  for (bool ex : {true, false}) {
    SCOPED_TRACE(ex ? "INFO_EX" : "INFO");
    FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
      if (f.header.type == uint8_t(p::MsgType::InfoGet)) {
        if (!ex) return pe.reply(info, f.header.seq);
        p::InfoEx x;
        x.info = info;
        x.table_max = 776;
        x.model_max = 4096;
        x.protocol_minor = 1;  // a 1.1 firmware: no RIG capability
        return pe.reply(x, f.header.seq);
      }
      if (f.header.type == uint8_t(p::MsgType::RigGet)) ADD_FAILURE() << "RIG_GET sent to a firmware without RIG";
      if (f.header.type == uint8_t(p::MsgType::XferBegin)) {
        p::Nack n;
        n.request_type = f.header.type;
        n.status = uint8_t(p::StatusCode::TooLarge);
        n.field = 2;
        return pe.reply(n, f.header.seq);
      }
    });
    Session s(fast_options());
    s.open(peer.path(), 115200);
    EXPECT_STREQ(s.call<p::Info>(p::InfoGet{}).firmware, "nlsoft-fake");
    Device d(s);
    EXPECT_EQ(d.handshake().platform, uint8_t(p::Platform::Hasel));
    EXPECT_EQ(d.transfer_limit(p::XferKind::RefTable), ex ? 776u : 0u);
    EXPECT_EQ(d.protocol_minor(), ex ? 1 : 0);
    EXPECT_FALSE(d.rig().has_value());
    EXPECT_EQ(d.rig_label(), "hasel") << "named by its platform, as before 1.2";
    try {
      d.upload(p::XferKind::RefTable, std::vector<uint8_t>(1000, 1));
      ADD_FAILURE() << "a too large upload was not refused";
    } catch (const NackError& e) {
      EXPECT_EQ(e.status(), p::StatusCode::TooLarge);
      const std::string what = e.what();
      EXPECT_EQ(what.find("at most 776 bytes") != std::string::npos, ex) << what;
    }
  }
}

// Protocol 1.2: a firmware with the RIG capability is asked for RIG_INFO in
// the handshake, and its rig's name is what the console shows.
TEST(Session, AFirmwareWithTheRigCapabilityIsAskedForItsRig) {
  p::Info info = board_info(p::Platform::Custom, "nlsoft-fake", 1);
  info.capabilities = p::capability::kRig;
  std::atomic<int> rig_gets{0};
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (f.header.type == uint8_t(p::MsgType::InfoGet)) {
      p::InfoEx x;
      x.info = info;
      return pe.reply(x, f.header.seq);
    }
    if (f.header.type == uint8_t(p::MsgType::RigGet)) {
      ++rig_gets;
      p::RigInfo r;
      std::snprintf(r.rig_name, sizeof r.rig_name, "%s", "lab-arm");
      r.rig_hash = 0x1234abcdu;
      r.m = r.n = r.w = r.nd = r.dd = 2;
      r.accept = p::shape_accept::kAny;
      return pe.reply(r, f.header.seq);
    }
  });
  Session s(fast_options());
  s.open(peer.path(), 115200);
  Device d(s);
  d.handshake();
  EXPECT_EQ(rig_gets.load(), 1);
  ASSERT_TRUE(d.rig().has_value());
  EXPECT_EQ(d.rig()->rig_hash, 0x1234abcdu);
  EXPECT_EQ(d.rig_label(), "lab-arm") << "not \"custom\": the rig names itself";
}

// The raw exchange: the bytes go out as given (here a byte per write, with
// a seq the caller chose), only a reply with that seq is taken, and every
// reply is shown to the reply tap.
TEST(Session, RawExchangeSendsTheBytesAsGivenAndMatchesItsSeq) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) {
    p::Ping req;
    if (p::unpack(f, req) != p::StatusCode::Ok) return;
    p::Pong reply;
    reply.nonce = req.nonce;
    // nonce 13 is answered with the wrong seq
    pe.reply(reply, req.nonce == 13 ? uint8_t(f.header.seq + 1) : f.header.seq);
  });
  Session s(fast_options());
  std::atomic<int> tapped{0};
  s.on_any_reply([&](const p::FrameView&) { ++tapped; });
  s.open(peer.path(), 115200);
  RawRequest req;
  req.wire = ping_wire(5, 77);
  req.type = uint8_t(p::MsgType::Ping);
  req.seq = 77;
  req.write_chunk = 1;
  const auto r = s.exchange(req);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->seq, 77);
  EXPECT_EQ(r->type, uint8_t(p::MsgType::Pong));
  EXPECT_EQ(peer.seqs_seen().back(), 77);

  req.wire = ping_wire(13, 78);
  req.seq = 78;
  req.write_chunk = 0;
  EXPECT_FALSE(s.exchange(req).has_value()) << "a reply with another seq was taken";
  EXPECT_EQ(tapped.load(), 2);
}

// A tool that counts the replies to a seq before it sends that seq again
// (the conformance probe) must find every counted reply already matched or
// discarded: a late duplicate it has counted must not answer the request it
// sends next. The peer answers nonce 1 twice (the second 100 ms later, as a
// firmware answers a retried copy from its stored reply); the tap dawdles
// 150 ms after counting the duplicate, so a request sent on its word would
// be pending while that duplicate is still in the session's hands.
TEST(Session, AReplyTheTapHasCountedCannotAnswerARequestSentAfterIt) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) {
    pong(pe, f);
    p::Ping req;
    if (p::unpack(f, req) == p::StatusCode::Ok && req.nonce == 1) {
      std::this_thread::sleep_for(100ms);
      pong(pe, f);
    }
  });
  Session s(fast_options());
  std::mutex m;
  std::condition_variable cv;
  int counted = 0;
  s.on_any_reply([&](const p::FrameView&) {
    int now = 0;
    {
      std::lock_guard<std::mutex> lock(m);
      now = ++counted;
    }
    cv.notify_all();
    if (now == 2) std::this_thread::sleep_for(150ms);
  });
  s.open(peer.path(), 115200);
  auto ping = [&](uint32_t nonce) {
    RawRequest r;
    r.wire = ping_wire(nonce, 90);
    r.type = uint8_t(p::MsgType::Ping);
    r.seq = 90;
    const auto reply = s.exchange(r);
    p::Pong pong;
    EXPECT_TRUE(reply.has_value());
    if (!reply) return uint32_t(0);
    EXPECT_EQ(reply->type, uint8_t(p::MsgType::Pong));
    EXPECT_EQ(p::unpack(reply->payload, reply->length, pong), p::StatusCode::Ok);
    return pong.nonce;
  };
  EXPECT_EQ(ping(1), 1u);
  {
    std::unique_lock<std::mutex> lock(m);
    ASSERT_TRUE(cv.wait_for(lock, 5s, [&] { return counted >= 2; })) << "the duplicate never came";
  }
  EXPECT_EQ(ping(2), 2u) << "the duplicate the tap had counted answered the request sent after it";
  EXPECT_EQ(s.stats().stale_replies, 1u);
}

}  // namespace
}  // namespace nlsoft::console
