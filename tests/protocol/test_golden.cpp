#include <gtest/gtest.h>

#include <set>
#include <string>

#include "protocol/catalog.hpp"
#include "protocol/encoder.hpp"
#include "protocol/host/golden_reader.hpp"
#include "protocol/host/message_text.hpp"

namespace np = nlsoft::protocol;
namespace golden = nlsoft::protocol::golden;

namespace {

class Golden : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::string error;
    ASSERT_TRUE(golden::read_file(NLSOFT_GOLDEN_VECTORS, vectors_, error)) << error;
  }
  static std::vector<golden::Vector> vectors_;
};

std::vector<golden::Vector> Golden::vectors_;

// One good frame and nothing else on the wire: exactly what an encoder emits.
bool is_single_frame(const golden::Vector& v) {
  size_t zeros = 0;
  for (uint8_t b : v.wire) zeros += (b == 0);
  return v.expect.size() == 1 && v.expect[0].rfind("frame ", 0) == 0 && zeros == 1 &&
         v.wire.back() == 0;
}

TEST_F(Golden, FileHasUniquelyNamedVectorsWithBytesAndExpectations) {
  ASSERT_GE(vectors_.size(), 40u);
  std::set<std::string> names;
  for (const auto& v : vectors_) {
    EXPECT_TRUE(names.insert(v.name).second) << "duplicate " << v.name;
    EXPECT_FALSE(v.wire.empty()) << v.name;
    EXPECT_FALSE(v.expect.empty()) << v.name;
  }
}

TEST_F(Golden, EveryMessageTypeHasAVector) {
  std::set<std::string> seen;
  for (const auto& v : vectors_) {
    for (const auto& e : v.expect) {
      if (e.rfind("frame ", 0) == 0) seen.insert(e.substr(6, e.find(' ', 6) - 6));
    }
  }
  for (const np::MsgInfo& m : np::kMessages) EXPECT_TRUE(seen.count(m.name)) << m.name;
}

TEST_F(Golden, EveryDecodeErrorReasonHasAVector) {
  std::set<std::string> seen;
  for (const auto& v : vectors_) {
    for (const auto& e : v.expect) {
      if (e.rfind("error ", 0) == 0) seen.insert(e.substr(6));
    }
  }
  for (unsigned i = 1; i < np::kFrameErrorCount; ++i) {
    const char* reason = np::to_string(static_cast<np::FrameError>(i));
    EXPECT_TRUE(seen.count(reason)) << reason;
  }
}

TEST_F(Golden, DecoderYieldsExactlyTheExpectedEventsForAnyChunking) {
  for (const auto& v : vectors_) {
    for (size_t chunk : {0u, 1u, 3u, 64u}) {
      EXPECT_EQ(golden::decode_events(v.wire, chunk), v.expect)
          << v.name << " (line " << v.line << ", chunk " << chunk << ")";
    }
  }
}

TEST_F(Golden, EncoderReproducesEverySingleFrameVectorByteForByte) {
  int checked = 0;
  for (const auto& v : vectors_) {
    if (!is_single_frame(v)) continue;
    np::text::ParsedFrame parsed;
    std::string error;
    ASSERT_TRUE(np::text::parse_frame(v.expect[0].substr(6), parsed, error))
        << v.name << ": " << error;
    uint8_t buf[np::kWireBufferSize];
    const size_t n = np::encode_frame(parsed.type, parsed.seq, parsed.flags,
                                      parsed.payload.data(), parsed.payload.size(), buf,
                                      sizeof buf);
    ASSERT_GT(n, 0u) << v.name;
    EXPECT_EQ(std::vector<uint8_t>(buf, buf + n), v.wire) << v.name;
    ++checked;
  }
  EXPECT_GE(checked, static_cast<int>(np::kMessageCount));
}

TEST_F(Golden, ExpectationsAreInCanonicalTextForm) {
  for (const auto& v : vectors_) {
    for (const auto& e : v.expect) {
      if (e.rfind("frame ", 0) != 0) continue;
      np::text::ParsedFrame parsed;
      std::string error;
      ASSERT_TRUE(np::text::parse_frame(e.substr(6), parsed, error)) << v.name << ": " << error;
      np::FrameView view;
      view.header.type = parsed.type;
      view.header.seq = parsed.seq;
      view.header.flags = parsed.flags;
      view.header.length = static_cast<uint8_t>(parsed.payload.size());
      view.payload = parsed.payload.data();
      EXPECT_EQ("frame " + np::text::format_frame(view), e) << v.name;
    }
  }
}

TEST(GoldenText, ParserRejectsMissingUnknownAndMalformedFields) {
  np::text::ParsedFrame f;
  std::string error;
  EXPECT_FALSE(np::text::parse_frame("PING seq=1 flags=0", f, error));
  EXPECT_FALSE(np::text::parse_frame("PING seq=1 flags=0 nonce=1 extra=2", f, error));
  EXPECT_FALSE(np::text::parse_frame("PING seq=1 flags=0 nonce=x", f, error));
  EXPECT_FALSE(np::text::parse_frame("PING seq=256 flags=0 nonce=1", f, error));
  EXPECT_FALSE(np::text::parse_frame("NOPE seq=1 flags=0", f, error));
  EXPECT_TRUE(np::text::parse_frame("PING seq=1 flags=0 nonce=0x10", f, error)) << error;
  EXPECT_EQ(f.payload, (std::vector<uint8_t>{0x10, 0, 0, 0}));
}

}  // namespace
