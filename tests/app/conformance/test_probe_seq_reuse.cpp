// The conformance probe sends a seq again on purpose (a duplicate; the same
// seq with another body). On a slow host a request is retried, and the answer
// to its second copy comes late: it must not be taken for the firmware's
// answer to the next request with that seq. Against a fake firmware on a pty
// that keeps the last reply, as the real one does, and answers its first two
// frames 400 ms late (the probe waits 200 ms, then sends a second copy).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <vector>

#include "app/conformance/probe.hpp"
#include "app/support/fake_peer.hpp"

namespace nlsoft::console::conformance {
namespace {

namespace p = nlsoft::protocol;
using test::FakePeer;
using namespace std::chrono_literals;

struct SlowStart {
  int frames = 0;
  uint8_t last_seq = 0;
  std::vector<uint8_t> last_body;
  p::Pong last_reply;
};

FakePeer::Handler slow_start_firmware(SlowStart& st) {
  return [&st](FakePeer& pe, const p::FrameView& f) {
    p::Ping ping;
    if (p::unpack(f, ping) != p::StatusCode::Ok) return;
    if (st.frames++ < 2) std::this_thread::sleep_for(400ms);
    const std::vector<uint8_t> body(f.payload, f.payload + f.header.length);
    if (st.frames == 1 || f.header.seq != st.last_seq || body != st.last_body) {
      st.last_reply.nonce = ping.nonce;  // executed
      st.last_seq = f.header.seq;
      st.last_body = body;
    }
    pe.reply(st.last_reply, f.header.seq);
  };
}

TEST(ProbeSeqReuse, ALateAnswerToARetriedCopyIsNotTakenForTheAnswerToTheSameSeqSentAgain) {
  SlowStart st;
  FakePeer peer(slow_start_firmware(st));
  Probe probe(200ms);
  probe.open(peer.path(), 115200);
  const uint8_t seq = probe.next_seq();
  p::Ping first;
  first.nonce = 0x8e2bd119u;
  p::Pong pong;
  ASSERT_TRUE(as(probe.exchange(uint8_t(p::MsgType::Ping), seq, Probe::wire(first, seq)), pong));
  EXPECT_EQ(pong.nonce, first.nonce);
  EXPECT_EQ(probe.late().requests, 1u) << "the first PING took a second copy";

  p::Ping other;
  other.nonce = first.nonce ^ 0xA5A5A5A5u;
  ASSERT_TRUE(as(probe.exchange(uint8_t(p::MsgType::Ping), seq, Probe::wire(other, seq)), pong));
  EXPECT_EQ(pong.nonce, other.nonce) << "the second copy's late answer was taken for this one";
  EXPECT_EQ(peer.requests_seen(), 3) << "two copies of the first PING, one of the second";
}

}  // namespace
}  // namespace nlsoft::console::conformance
