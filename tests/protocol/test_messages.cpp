#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "protocol/catalog.hpp"
#include "protocol/messages.hpp"
#include "test_util.hpp"

namespace np = nlsoft::protocol;
using namespace nlsoft::protocol::test;

namespace {

template <class M>
M round_trip(const M& in) {
  uint8_t buf[np::kMaxPayload];
  size_t len = 0;
  EXPECT_EQ(np::pack(in, buf, sizeof buf, len), np::StatusCode::Ok);
  M out;
  EXPECT_EQ(np::unpack(buf, len, out), np::StatusCode::Ok);
  return out;
}

TEST(Messages, ParamSetCarriesAWholeVectorInOneMessage) {
  np::ParamSet in;
  in.id = 4;
  in.count = np::kMaxParamValues;
  for (uint8_t i = 0; i < in.count; ++i) in.set_f32(i, 0.5f * i);
  const np::ParamSet out = round_trip(in);
  EXPECT_EQ(out.id, 4);
  ASSERT_EQ(out.count, np::kMaxParamValues);
  for (uint8_t i = 0; i < out.count; ++i) EXPECT_EQ(out.f32(i), 0.5f * i);
}

TEST(Messages, FloatsKeepTheirExactBitsIncludingNaNPayloadsAndNegativeZero) {
  np::ParamValue in;
  in.id = 1;
  in.type = static_cast<uint8_t>(np::ParamType::F32);
  in.count = 3;
  in.values[0] = 0x7FC01234u;
  in.values[1] = 0x80000000u;
  in.values[2] = 0x00000001u;
  const np::ParamValue out = round_trip(in);
  EXPECT_EQ(out.values[0], 0x7FC01234u);
  EXPECT_EQ(out.values[1], 0x80000000u);
  EXPECT_EQ(out.values[2], 0x00000001u);
}

TEST(Messages, PackRefusesCountsBeyondCapacityAndEmptyRequiredTails) {
  uint8_t buf[np::kMaxPayload];
  size_t len = 0;
  np::ParamSet too_many;
  too_many.count = np::kMaxParamValues + 1;
  EXPECT_EQ(np::pack(too_many, buf, sizeof buf, len), np::StatusCode::BadLength);
  np::ParamSet none;
  EXPECT_EQ(np::pack(none, buf, sizeof buf, len), np::StatusCode::BadLength);
  np::ParamDesc unnamed;  // a parameter needs a name
  EXPECT_EQ(np::pack(unnamed, buf, sizeof buf, len), np::StatusCode::BadLength);
}

TEST(Messages, PackRefusesAnOutputBufferTooSmall) {
  np::Status s;
  uint8_t buf[51];
  size_t len = 0;
  EXPECT_EQ(np::pack(s, buf, sizeof buf, len), np::StatusCode::BadLength);
}

TEST(Messages, UnpackRefusesShortLongAndMisalignedPayloads) {
  uint8_t buf[np::kMaxPayload] = {};
  np::Ping ping;
  EXPECT_EQ(np::unpack(buf, 3, ping), np::StatusCode::BadLength);
  EXPECT_EQ(np::unpack(buf, 5, ping), np::StatusCode::BadLength);
  np::ParamSet set;
  EXPECT_EQ(np::unpack(buf, 7, set), np::StatusCode::BadLength);  // 2 + 5 is not 2 + 4k
  EXPECT_EQ(np::unpack(buf, 6, set), np::StatusCode::Ok);
  EXPECT_EQ(set.count, 1);
}

TEST(Messages, UnpackOfAFrameOfAnotherTypeIsRefused) {
  np::Ping p;
  const Bytes w = wire_of(p);
  np::Decoder d;
  np::DecodeResult r;
  d.feed(w.data(), w.size(), r);
  ASSERT_EQ(r.kind, np::DecodeResult::Kind::Frame);
  np::Pong pong;
  EXPECT_EQ(np::unpack(r.frame, pong), np::StatusCode::Unsupported);
}

TEST(Messages, TextFieldsRoundTripAndRejectOverlongText) {
  np::Log log;
  log.level = 3;
  std::memset(log.text, 'x', np::kMaxLogText);
  EXPECT_EQ(std::string(round_trip(log).text), std::string(np::kMaxLogText, 'x'));

  np::ParamDesc d;
  d.size = 1;
  std::strcpy(d.name, "lambda");
  std::strcpy(d.unit, "N/kg");
  const np::ParamDesc out = round_trip(d);
  EXPECT_STREQ(out.name, "lambda");
  EXPECT_STREQ(out.unit, "N/kg");
}

TEST(Messages, NulBytesInsideWireTextAreShownAsQuestionMarks) {
  const uint8_t payload[] = {1, 'a', 0, 'b'};
  np::Log log;
  ASSERT_EQ(np::unpack(payload, sizeof payload, log), np::StatusCode::Ok);
  EXPECT_STREQ(log.text, "a?b");
}

TEST(Messages, TelemetryCarriesOnlyTheFieldsInItsMask) {
  np::Telemetry t;
  t.tseq = 7;
  t.n = 3;
  t.m = 6;
  t.mask = np::telemetry_field::kYHat | np::telemetry_field::kCost;
  t.y_hat[0] = 1.0f;
  t.y_hat[2] = -2.0f;
  t.cost = 9.0f;
  t.step = 1234;  // not in the mask: must not travel
  uint8_t buf[np::kMaxPayload];
  size_t len = 0;
  ASSERT_EQ(np::pack(t, buf, sizeof buf, len), np::StatusCode::Ok);
  EXPECT_EQ(len, 4u + 12u + 4u);
  np::Telemetry out;
  ASSERT_EQ(np::unpack(buf, len, out), np::StatusCode::Ok);
  EXPECT_EQ(out.step, 0u);
  EXPECT_EQ(out.y_hat[2], -2.0f);
  EXPECT_EQ(out.cost, 9.0f);
}

TEST(Messages, TelemetryWithEveryFieldForHaselIs81PayloadBytes) {
  EXPECT_EQ(np::telemetry_payload_size(np::telemetry_field::kAll, 3, 6), 81u);
  np::Telemetry t;
  t.mask = np::telemetry_field::kAll;
  t.n = 3;
  t.m = 6;
  EXPECT_EQ(wire_of(t).size(), 90u);  // MAVLink 2 would spend 12 bytes on framing alone
}

TEST(Messages, TelemetryThatCannotFitIsRefused) {
  np::Telemetry t;
  t.mask = np::telemetry_field::kAll;
  t.n = 15;
  t.m = 15;
  uint8_t buf[np::kMaxPayload];
  size_t len = 0;
  EXPECT_EQ(np::pack(t, buf, sizeof buf, len), np::StatusCode::BadLength);
}

// Rebuilds each type's signature and length rule from its struct's field
// list, so the catalogue (and with it PROTOCOL.md's CRC seeds) cannot drift
// from the code that packs the bytes.
struct ShapeVisitor {
  std::string sig;
  size_t fixed = 0;
  size_t tail_elem = 0;
  size_t tail_cap = 0;

  void add(const std::string& s) { sig += (sig.empty() ? "" : ",") + s; }
  void u8(const char* k, uint8_t) {
    add(std::string("u8 ") + k);
    fixed += 1;
  }
  void u16(const char* k, uint16_t) {
    add(std::string("u16 ") + k);
    fixed += 2;
  }
  void u32(const char* k, uint32_t) {
    add(std::string("u32 ") + k);
    fixed += 4;
  }
  void f32(const char* k, float) {
    add(std::string("f32 ") + k);
    fixed += 4;
  }
  void nibbles(const char* a, uint8_t, const char* b, uint8_t) {
    add(std::string("u4 ") + a + ",u4 " + b);
    fixed += 1;
  }
  void f32_array(const char* k, const float*, uint8_t count, uint8_t) {
    add("f32[" + std::to_string(count) + "] " + k);
    fixed += 4u * count;
  }
  void tail(const std::string& s, size_t elem, size_t cap) {
    add(s);
    tail_elem = elem;
    tail_cap = cap;
  }
  void f32_tail(const char* k, const float*, uint8_t, uint8_t cap) {
    tail(std::string("f32[] ") + k, 4, cap);
  }
  void word_tail(const char* k, const uint32_t*, uint8_t, uint8_t cap, np::ParamType) {
    tail(std::string("u32[] ") + k, 4, cap);
  }
  void bytes_tail(const char* k, const uint8_t*, uint8_t, uint8_t cap) {
    tail(std::string("u8[] ") + k, 1, cap);
  }
  void text_tail(const char* k, const char*, uint8_t cap) { tail(std::string("char[] ") + k, 1, cap); }
  void text_fixed(const char* k, const char*, uint8_t size) {
    add("char[" + std::to_string(size) + "] " + k);
    fixed += size;
  }
};

TEST(Messages, CatalogueSignaturesAndLengthRulesMatchTheStructFieldLists) {
  for (const np::MsgInfo& info : np::kMessages) {
    // Lengths computed from the payload: covered by their own tests.
    if (info.type == np::MsgType::Telemetry || info.type == np::MsgType::IdentSample) continue;
    np::with_message_type(static_cast<uint8_t>(info.type), [&](auto msg) {
      ShapeVisitor v;
      decltype(msg)::fields(msg, v);
      EXPECT_EQ(std::string(info.name) + ":" + v.sig, info.signature);
      EXPECT_GE(info.min_len, v.fixed) << info.name;
      EXPECT_EQ(info.max_len, v.fixed + v.tail_elem * v.tail_cap) << info.name;
      EXPECT_EQ(info.step, v.tail_elem == 0 ? 1u : v.tail_elem) << info.name;
      if (v.tail_elem == 0) {
        EXPECT_EQ(info.min_len, info.max_len) << info.name;
      }
      EXPECT_LE(info.max_len, np::kMaxPayload) << info.name;
    });
  }
}

// IDENT_SAMPLE's three vectors take their counts from its m, n, w bytes:
// the signature names them, and the length rule is 13 + 4 (m + n + w).
TEST(Messages, IdentSampleLengthFollowsItsCountsAndItsSignatureNamesThem) {
  np::IdentSample s;
  s.tseq = 9;
  s.m = 2;
  s.n = 3;
  s.w = 4;
  s.step = 77;
  for (int i = 0; i < 4; ++i) s.l[i] = float(i) + 0.5f;
  s.u[1] = -1.0f;
  s.y[2] = 2.0f;
  ShapeVisitor v;
  np::IdentSample::fields(s, v);
  EXPECT_EQ("IDENT_SAMPLE:" + v.sig,
            "IDENT_SAMPLE:u16 tseq,u8 m,u8 n,u8 w,u32 step,u32 time_us,f32[2] u,f32[3] y,f32[4] l");
  EXPECT_EQ(v.fixed, np::ident_sample_payload_size(2, 3, 4));
  uint8_t buf[np::kMaxPayload];
  size_t len = 0;
  ASSERT_EQ(np::pack(s, buf, sizeof buf, len), np::StatusCode::Ok);
  EXPECT_EQ(len, 13u + 4u * 9u);
  np::IdentSample back;
  ASSERT_EQ(np::unpack(buf, len, back), np::StatusCode::Ok);
  EXPECT_EQ(back.step, 77u);
  EXPECT_EQ(back.u[1], -1.0f);
  EXPECT_EQ(back.y[2], 2.0f);
  EXPECT_EQ(back.l[3], 3.5f);
  // A count that disagrees with the length fails the length rule.
  buf[4] = 5;
  EXPECT_EQ(np::unpack(buf, len, back), np::StatusCode::BadLength);
  // More floats than a payload holds cannot be packed.
  s.m = 20, s.n = 20, s.w = 19;
  EXPECT_EQ(np::pack(s, buf, sizeof buf, len), np::StatusCode::BadLength);
}

TEST(Messages, EveryCatalogueTypeHasAStructAndRequestsAndRepliesAreInSeparateRanges) {
  for (const np::MsgInfo& info : np::kMessages) {
    const auto t = static_cast<uint8_t>(info.type);
    EXPECT_TRUE(np::with_message_type(t, [](auto) {})) << info.name;
    EXPECT_EQ(info.is_request, t < 0x40) << info.name;
  }
  EXPECT_FALSE(np::with_message_type(0x00, [](auto) {}));
}

}  // namespace
