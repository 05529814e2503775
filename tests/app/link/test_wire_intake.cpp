// The console's intake of what a firmware sends, checked where bytes
// become values: sample frames of another shape than INFO's or carrying
// NaN are dropped and counted lost (an IDENT_SAMPLE with n = 58 once wrote
// 15 floats past a Sample), implausible INFO is refused, the firmware's
// text is escaped where it is decoded, an upload's wait is bounded however
// the firmware acknowledges, and a chip count outside 1..8 is refused.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "app/link/device.hpp"
#include "app/link/info_check.hpp"
#include "app/link/link_error.hpp"
#include "app/link/sample_check.hpp"
#include "app/link/session.hpp"
#include "app/record/sample.hpp"
#include "app/support/fake_peer.hpp"
#include "host/files/printable.hpp"

namespace nlsoft::console {

using host::printable;
using host::printable_into;
using host::printable_within;

namespace {

namespace p = nlsoft::protocol;
using test::FakePeer;
using namespace std::chrono_literals;

p::Info small_info() {
  p::Info info;
  info.platform = uint8_t(p::Platform::Msd);
  info.m = 1;
  info.n = 1;
  info.w = 0;
  info.loop_rate_hz = 100;
  info.capabilities = p::capability::kXferModel;
  std::snprintf(info.firmware, sizeof info.firmware, "%s", "fake");
  return info;
}

// The frame of the report: after the handshake, m = 0, n = 58, w = 0; 13 +
// 4 * 58 = 245 bytes, which the protocol's length rule accepts.
p::IdentSample hostile_ident_sample(uint16_t tseq) {
  p::IdentSample s;
  s.tseq = tseq;
  s.m = 0;
  s.n = 58;
  s.w = 0;
  for (float& y : s.y) y = 1e30f;
  return s;
}

SessionOptions quick() {
  SessionOptions o;
  o.timeout = 100ms;
  o.tries = 3;
  o.keepalive = 0ms;
  o.silence_limit = 10s;
  return o;
}

TEST(SampleCheck, AFrameOfAnotherShapeThanInfoIsRefusedInWords) {
  const p::Info info = small_info();
  const p::IdentSample bad = hostile_ident_sample(1);
  EXPECT_EQ(ident_sample_fault(bad, &info), SampleFault::Dimensions);
  EXPECT_EQ(ident_sample_fault(bad, nullptr), SampleFault::Dimensions) << "58 outputs fit no sample, INFO or not";
  EXPECT_EQ(ident_sample_refusal(bad, &info),
            "an IDENT_SAMPLE frame with m=0 n=58 w=0, the firmware's INFO says m=1 n=1 w=0");
  p::IdentSample good;
  good.m = 1;
  good.n = 1;
  EXPECT_EQ(ident_sample_fault(good, &info), SampleFault::None);
  good.n = 0;  // no output measured: allowed (PROTOCOL.md 7)
  EXPECT_EQ(ident_sample_fault(good, &info), SampleFault::None);
  good.w = 1;
  EXPECT_EQ(ident_sample_fault(good, &info), SampleFault::Dimensions);

  p::Telemetry t;
  t.mask = p::telemetry_field::kAll;
  t.n = 2;
  t.m = 1;
  EXPECT_EQ(telemetry_fault(t, &info), SampleFault::Dimensions);
  t.n = 1;
  EXPECT_EQ(telemetry_fault(t, &info), SampleFault::None);
}

TEST(SampleCheck, NanOrInfinityIsNeverScored) {
  const p::Info info = small_info();
  p::Telemetry t;
  t.mask = p::telemetry_field::kAll;
  t.n = 1;
  t.m = 1;
  t.y_true[0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(telemetry_fault(t, &info), SampleFault::NotFinite);
  t.y_true[0] = 0;
  t.cost = std::numeric_limits<float>::infinity();
  EXPECT_EQ(telemetry_fault(t, &info), SampleFault::NotFinite);
  t.cost = 0;
  t.u[0] = -std::numeric_limits<float>::infinity();
  EXPECT_EQ(telemetry_fault(t, &info), SampleFault::NotFinite);
  // A field the mask leaves out is not read, whatever its bytes.
  t.mask = uint8_t(p::telemetry_field::kAll & ~p::telemetry_field::kU);
  EXPECT_EQ(telemetry_fault(t, &info), SampleFault::None);

  p::IdentSample s;
  s.m = 1;
  s.n = 1;
  s.y[0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(ident_sample_fault(s, &info), SampleFault::NotFinite);
}

// Whatever reaches it, a Sample's vectors stay inside it: y_true() is placed
// by n, so an n kept at 58 put it past v.
TEST(SampleFrom, AnIdentSampleNeverPlacesItsVectorsPastTheSample) {
  const Sample s = sample_from(hostile_ident_sample(1), 0);
  EXPECT_LE(int(s.n), int(p::kMaxTelemetryDim));
  EXPECT_LE(int(s.m), int(p::kMaxTelemetryDim));
  EXPECT_LE(s.u() + s.m, s.v + Sample::kMaxFloats);
  EXPECT_LE(s.y_true() + s.n, s.v + Sample::kMaxFloats);
}

TEST(InfoCheck, ImplausibleInfoIsRefusedWithTheReason) {
  p::Info info = small_info();
  EXPECT_EQ(info_refusal(info), "");
  info.loop_rate_hz = 0;
  EXPECT_NE(info_refusal(info).find("loop rate of 0 Hz"), std::string::npos) << info_refusal(info);
  info.loop_rate_hz = 0xFFFFFFFFu;
  EXPECT_NE(info_refusal(info).find("loop rate of 4294967295 Hz"), std::string::npos) << info_refusal(info);
  info.loop_rate_hz = kMaxLoopRateHz;
  EXPECT_EQ(info_refusal(info), "");
  info.n = 0;
  EXPECT_NE(info_refusal(info).find("impossible dimensions"), std::string::npos);
  info.n = 15;
  info.m = 15;
  info.w = 29;  // 59 floats: no IDENT_SAMPLE holds them
  EXPECT_NE(info_refusal(info).find("m + n + w at most 58"), std::string::npos) << info_refusal(info);
  info.w = 28;
  EXPECT_EQ(info_refusal(info), "");
}

TEST(Printable, EscapesEveryWayTextCanActOnATerminal) {
  // OSC 52 (clipboard), a screen clear, a title, a cursor move.
  EXPECT_EQ(printable("\x1b]52;c;aGk=\x07\x1b[2J\x1b]0;t\x07\x1b[1;1H"),
            "\\x1b]52;c;aGk=\\x07\\x1b[2J\\x1b]0;t\\x07\\x1b[1;1H");
  // C1 controls: as UTF-8 (U+009B) and as the raw 8-bit byte.
  EXPECT_EQ(printable("a\xc2\x9b" "2Jb"), "a\\u009b2Jb");
  EXPECT_EQ(printable("a\x9b" "2Jb"), "a\\x9b2Jb");
  EXPECT_EQ(printable("\x85"), "\\x85");
  // Bidi overrides and isolates: U+202E, U+2066, U+2069.
  EXPECT_EQ(printable("x\xe2\x80\xae" "y"), "x\\u202ey");
  EXPECT_EQ(printable("\xe2\x81\xa6" "z\xe2\x81\xa9"), "\\u2066z\\u2069");
  // Not UTF-8: a cut sequence, an overlong '/', a surrogate, 0xff.
  EXPECT_EQ(printable("\xe2\x80"), "\\xe2\\x80");
  EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");
  EXPECT_EQ(printable("\xff"), "\\xff");
  // Text that is only text stays as it is.
  EXPECT_EQ(printable("5 \xc2\xb5m, \xe2\x86\x92 ok"), "5 \xc2\xb5m, \xe2\x86\x92 ok");
}

TEST(Printable, AFixedFieldIsCutAtACharacterNeverInsideOne) {
  EXPECT_EQ(printable_within("abc", 3), "abc");
  const std::string cut = printable_within("\x1b\x1b\x1b", 8);  // "\x1b\x1b\x1b" escaped is 12 bytes
  EXPECT_LE(cut.size(), 8u);
  EXPECT_EQ(cut, "\\x1b\\…");
  const std::string utf = printable_within("\xc2\xb5\xc2\xb5\xc2\xb5", 5);
  EXPECT_EQ(utf, "\xc2\xb5…") << "the second µ is not cut in two";
  char field[8] = "\x1b[2J\x1b";  // escaped: 11 bytes for 7
  printable_into(field, field, sizeof field);
  EXPECT_STREQ(field, "\\x1b…");
}

// The report's frame, after the handshake, on the session: dropped before
// any handler sees it, counted, said once, and the next frame shows it lost.
TEST(Session, AnIdentSampleOfAnotherShapeThanInfoIsDroppedCountedAndSaidOnce) {
  const p::Info info = small_info();
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (f.header.type == uint8_t(p::MsgType::InfoGet)) return pe.reply(info, f.header.seq);
    if (f.header.type != uint8_t(p::MsgType::Ping)) return;
    pe.send_unsolicited(hostile_ident_sample(7));
    pe.send_unsolicited(hostile_ident_sample(8));
    p::IdentSample ok;
    ok.tseq = 9;
    ok.m = 1;
    ok.n = 1;
    ok.y[0] = 0.5f;
    pe.send_unsolicited(ok);
    p::Log log;
    log.level = 1;
    std::snprintf(log.text, sizeof log.text, "%s", "\x1b]52;c;ZXZpbA==\x07\x1b[2Jfake\nline");
    pe.send_unsolicited(log);
    p::Ping ping;
    if (p::unpack(f, ping) != p::StatusCode::Ok) return;
    p::Pong pong;
    pong.nonce = ping.nonce;
    pe.reply(pong, f.header.seq);
  });
  Session s(quick());
  std::mutex mu;
  std::vector<p::IdentSample> taken;
  std::vector<uint32_t> lost;
  std::vector<LinkEvent> events;
  std::string logged;
  s.on_ident_sample([&](const p::IdentSample& t, uint32_t l) {
    std::lock_guard<std::mutex> lock(mu);
    taken.push_back(t);
    lost.push_back(l);
  });
  s.on_log([&](const p::Log& l) {
    std::lock_guard<std::mutex> lock(mu);
    logged = l.text;
  });
  s.on_event([&](const LinkEvent& e) {
    std::lock_guard<std::mutex> lock(mu);
    events.push_back(e);
  });
  s.open(peer.path(), 115200);
  Device d(s);
  d.handshake();
  p::Ping ping;
  ping.nonce = 3;
  s.call<p::Pong>(ping);  // the frames before the PONG have been handled when it returns
  // The Refused event goes through the supervisor: wait for it, bounded.
  for (int i = 0; i < 200; ++i) {
    {
      std::lock_guard<std::mutex> lock(mu);
      if (!events.empty()) break;
    }
    std::this_thread::sleep_for(10ms);
  }
  s.close();
  std::lock_guard<std::mutex> lock(mu);
  ASSERT_EQ(taken.size(), 1u) << "only the frame of INFO's shape is passed on";
  EXPECT_EQ(taken[0].n, 1);
  EXPECT_EQ(lost[0], 0u) << "no frame counted before it";
  EXPECT_EQ(s.stats().refused_frames, 2u);
  ASSERT_EQ(events.size(), 1u) << "said once, not once per frame";
  EXPECT_EQ(events[0].kind, LinkEvent::Kind::Refused);
  EXPECT_NE(events[0].detail.find("dropped an IDENT_SAMPLE frame with m=0 n=58 w=0"), std::string::npos)
      << events[0].detail;
  EXPECT_EQ(logged, "\\x1b]52;c;ZXZpbA==\\x07\\x1b[2Jfake\\nline") << "escaped where it was decoded";
}

// A refused frame between two good ones is counted as lost by the next.
TEST(Session, ARefusedTelemetryFrameIsCountedLost) {
  const p::Info info = small_info();
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (f.header.type == uint8_t(p::MsgType::InfoGet)) return pe.reply(info, f.header.seq);
    if (f.header.type != uint8_t(p::MsgType::Ping)) return;
    p::Telemetry t;
    t.mask = p::telemetry_field::kStep | p::telemetry_field::kYTrue;
    t.n = 1;
    t.m = 1;
    for (uint16_t seq : {uint16_t(1), uint16_t(2), uint16_t(3)}) {
      t.tseq = seq;
      t.step = seq;
      t.y_true[0] = seq == 2 ? std::numeric_limits<float>::quiet_NaN() : 0.f;
      pe.send_unsolicited(t);
    }
    p::Ping ping;
    if (p::unpack(f, ping) != p::StatusCode::Ok) return;
    p::Pong pong;
    pong.nonce = ping.nonce;
    pe.reply(pong, f.header.seq);
  });
  Session s(quick());
  std::atomic<int> frames{0};
  std::atomic<uint32_t> lost{0};
  s.on_telemetry([&](const p::Telemetry& t, uint32_t l) {
    EXPECT_TRUE(std::isfinite(t.y_true[0]));
    ++frames;
    lost += l;
  });
  s.open(peer.path(), 115200);
  Device(s).handshake();
  p::Ping ping;
  s.call<p::Pong>(ping);
  s.close();
  EXPECT_EQ(frames.load(), 2);
  EXPECT_EQ(lost.load(), 1u);
  EXPECT_EQ(s.stats().refused_frames, 1u);
}

TEST(Device, ImplausibleInfoIsRefusedAtTheHandshake) {
  p::Info info = small_info();
  info.loop_rate_hz = 0;
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (f.header.type == uint8_t(p::MsgType::InfoGet)) pe.reply(info, f.header.seq);
  });
  Session s(quick());
  s.open(peer.path(), 115200);
  Device d(s);
  try {
    d.handshake();
    ADD_FAILURE() << "a loop rate of 0 Hz was taken";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("loop rate of 0 Hz"), std::string::npos) << e.what();
  }
}

TEST(Device, TheFirmwareNameIsEscapedWhereItIsDecoded) {
  p::Info info = small_info();
  std::snprintf(info.firmware, sizeof info.firmware, "%s", "fw\nLambda 1e11\nQ 0");
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (f.header.type == uint8_t(p::MsgType::InfoGet)) pe.reply(info, f.header.seq);
  });
  Session s(quick());
  s.open(peer.path(), 115200);
  Device d(s);
  EXPECT_STREQ(d.handshake().firmware, "fw\\nLambda 1e11\\nQ 0");
  EXPECT_STREQ(d.info().firmware, "fw\\nLambda 1e11\\nQ 0");
}

// XFER_ACK offsets that go forward and back: the upload ends, in words,
// after a bounded number of chunks.
TEST(Device, AnUploadWhoseOffsetsGoBackAndForthEnds) {
  const p::Info info = small_info();
  std::atomic<int> chunks{0};
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (f.header.type == uint8_t(p::MsgType::InfoGet)) return pe.reply(info, f.header.seq);
    p::XferAck ack;
    ack.kind = uint8_t(p::XferKind::Model);
    ack.total_size = 2000;
    if (f.header.type == uint8_t(p::MsgType::XferBegin)) return pe.reply(ack, f.header.seq);
    if (f.header.type != uint8_t(p::MsgType::XferChunk)) return;
    ack.next_offset = ++chunks % 2 == 1 ? 241 : 0;
    pe.reply(ack, f.header.seq);
  });
  Session s(quick());
  s.open(peer.path(), 115200);
  Device d(s);
  d.handshake();
  try {
    d.upload(p::XferKind::Model, std::vector<uint8_t>(2000, 7));
    ADD_FAILURE() << "the upload was taken as done";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("upload"), std::string::npos) << e.what();
  }
  EXPECT_LE(chunks.load(), 2 * 9 + 16) << "at most twice the chunks of 2000 bytes, and the retries";
}

// A signal (the console's give-up) ends an upload between chunks.
TEST(Device, AnUploadEndsWhenTheConsoleGivesUp) {
  const p::Info info = small_info();
  std::atomic<int> chunks{0};
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (f.header.type == uint8_t(p::MsgType::InfoGet)) return pe.reply(info, f.header.seq);
    p::XferAck ack;
    ack.kind = uint8_t(p::XferKind::Model);
    ack.total_size = 100000;
    if (f.header.type == uint8_t(p::MsgType::XferChunk)) ack.next_offset = uint32_t(241 * ++chunks);
    if (f.header.type == uint8_t(p::MsgType::XferBegin) || f.header.type == uint8_t(p::MsgType::XferChunk))
      pe.reply(ack, f.header.seq);
  });
  Session s(quick());
  s.open(peer.path(), 115200);
  Device d(s);
  d.handshake();
  d.set_give_up([&] { return chunks.load() >= 3; });
  try {
    d.upload(p::XferKind::Model, std::vector<uint8_t>(100000, 7));
    ADD_FAILURE() << "the upload did not stop";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("upload interrupted at byte 723"), std::string::npos) << e.what();
  }
  EXPECT_EQ(chunks.load(), 3);
}

TEST(Device, AChipCountOutsideOneToEightIsRefused) {
  p::Info info = small_info();
  info.capabilities |= p::capability::kDevices;
  std::atomic<int> asked{0};
  FakePeer peer([&](FakePeer& pe, const p::FrameView& f) {
    if (f.header.type == uint8_t(p::MsgType::InfoGet)) return pe.reply(info, f.header.seq);
    p::DeviceGet get;
    if (p::unpack(f, get) != p::StatusCode::Ok) return;
    ++asked;
    p::DeviceStatus d;
    d.index = get.index;
    d.count = 200;
    std::snprintf(d.name, sizeof d.name, "%s", "mag1");  // DEVICE_STATUS names its chip (1..32 bytes)
    pe.reply(d, f.header.seq);
  });
  Session s(quick());
  s.open(peer.path(), 115200);
  Device d(s);
  d.handshake();
  try {
    d.devices();
    ADD_FAILURE() << "200 chips were listed";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("1..8 chips"), std::string::npos) << e.what();
  }
  EXPECT_EQ(asked.load(), 1) << "refused at the first answer";
}

}  // namespace
}  // namespace nlsoft::console
