// The conformance probe's fence (send_fenced): bytes that must get no reply
// are followed by a PING, and whatever the firmware answered them with is
// what arrives before the PONG. Against a fake firmware on a pty that does
// or does not answer a request carrying the REPLY flag.
#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "app/conformance/probe.hpp"
#include "app/support/fake_peer.hpp"

namespace nlsoft::console::conformance {
namespace {

namespace p = nlsoft::protocol;
using test::FakePeer;
using namespace std::chrono_literals;

// A firmware that answers every PING, or only those without the REPLY flag.
FakePeer::Handler firmware(bool answers_reply_flag) {
  return [answers_reply_flag](FakePeer& pe, const p::FrameView& f) {
    p::Ping ping;
    if (p::unpack(f, ping) != p::StatusCode::Ok) return;
    if ((f.header.flags & p::frame_flags::kReply) && !answers_reply_flag) return;
    p::Pong pong;
    pong.nonce = ping.nonce;
    pe.reply(pong, f.header.seq);
  };
}

std::vector<Frame> fenced(FakePeer& peer, Frame& answer, uint32_t fence_nonce) {
  Probe probe(200ms);
  probe.open(peer.path(), 115200);
  p::Ping bogus;
  bogus.nonce = 7;
  const uint8_t seq = probe.next_seq();
  p::Ping fence;
  fence.nonce = fence_nonce;
  return probe.send_fenced(Probe::wire(bogus, seq, p::frame_flags::kReply), fence, answer);
}

TEST(ProbeFence, AFirmwareThatAnswersWhatItMustNotIsHeardBeforeTheFence) {
  FakePeer peer(firmware(true));
  Frame answer;
  const auto heard = fenced(peer, answer, 0x5eed);
  ASSERT_EQ(heard.size(), 1u) << "the answer to the REPLY-flagged PING";
  EXPECT_EQ(heard[0].type, uint8_t(p::MsgType::Pong));
  p::Pong pong;
  ASSERT_TRUE(as(answer, pong));
  EXPECT_EQ(pong.nonce, 0x5eedu) << "the fence's own answer";
}

TEST(ProbeFence, AConformingFirmwareIsHeardSayingNothingAndTheFenceIsAnswered) {
  FakePeer peer(firmware(false));
  Frame answer;
  const auto heard = fenced(peer, answer, 0xfe2ce);
  EXPECT_TRUE(heard.empty()) << heard.size() << " frames heard (the fence's own PONG is not one)";
  p::Pong pong;
  ASSERT_TRUE(as(answer, pong));
  EXPECT_EQ(pong.nonce, 0xfe2ceu);
  EXPECT_EQ(peer.requests_seen(), 2) << "the bytes and one fence, no retry";
}

}  // namespace
}  // namespace nlsoft::console::conformance
