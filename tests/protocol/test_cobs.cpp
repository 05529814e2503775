#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "protocol/cobs.hpp"

namespace np = nlsoft::protocol;
using Bytes = std::vector<uint8_t>;

namespace {

Bytes encode(const Bytes& in) {
  Bytes out(np::cobs_max_encoded_size(in.size()));
  const size_t n = np::cobs_encode(in.data(), in.size(), out.data(), out.size());
  out.resize(n);
  return out;
}

Bytes decode(const Bytes& in, bool* ok = nullptr) {
  Bytes out(in.size() + 1);
  const np::CobsDecodeResult r = np::cobs_decode(in.data(), in.size(), out.data(), out.size());
  if (ok) *ok = r.ok;
  out.resize(r.size);
  return out;
}

Bytes range(unsigned first, unsigned last) {
  Bytes b;
  for (unsigned i = first; i <= last; ++i) b.push_back(static_cast<uint8_t>(i));
  return b;
}

Bytes cat(Bytes a, const Bytes& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The examples of the COBS paper / Wikipedia article.
TEST(Cobs, EncodesTheReferenceExamples) {
  EXPECT_EQ(encode({}), (Bytes{0x01}));
  EXPECT_EQ(encode({0x00}), (Bytes{0x01, 0x01}));
  EXPECT_EQ(encode({0x00, 0x00}), (Bytes{0x01, 0x01, 0x01}));
  EXPECT_EQ(encode({0x00, 0x11, 0x00}), (Bytes{0x01, 0x02, 0x11, 0x01}));
  EXPECT_EQ(encode({0x11, 0x22, 0x00, 0x33}), (Bytes{0x03, 0x11, 0x22, 0x02, 0x33}));
  EXPECT_EQ(encode({0x11, 0x22, 0x33, 0x44}), (Bytes{0x05, 0x11, 0x22, 0x33, 0x44}));
  EXPECT_EQ(encode({0x11, 0x00, 0x00, 0x00}), (Bytes{0x02, 0x11, 0x01, 0x01, 0x01}));
  EXPECT_EQ(encode(range(0x01, 0xFE)), cat({0xFF}, range(0x01, 0xFE)));
  EXPECT_EQ(encode(cat({0x00}, range(0x01, 0xFE))), cat({0x01, 0xFF}, range(0x01, 0xFE)));
  EXPECT_EQ(encode(range(0x01, 0xFF)), cat(cat({0xFF}, range(0x01, 0xFE)), {0x02, 0xFF}));
}

TEST(Cobs, DecodesTheReferenceExamples) {
  EXPECT_EQ(decode({0x01}), Bytes{});
  EXPECT_EQ(decode({0x03, 0x11, 0x22, 0x02, 0x33}), (Bytes{0x11, 0x22, 0x00, 0x33}));
  EXPECT_EQ(decode(cat(cat({0xFF}, range(0x01, 0xFE)), {0x02, 0xFF})), range(0x01, 0xFF));
}

TEST(Cobs, AcceptsTheRedundantCodeSomeEncodersAppendAfterAFullBlock) {
  bool ok = false;
  EXPECT_EQ(decode(cat(cat({0xFF}, range(0x01, 0xFE)), {0x01}), &ok), range(0x01, 0xFE));
  EXPECT_TRUE(ok);
}

TEST(Cobs, RoundTripsRandomBuffersOfEverySizeUpTo600) {
  std::mt19937 rng(1234);
  for (size_t size = 0; size <= 600; ++size) {
    Bytes in(size);
    const auto zero_odds = static_cast<unsigned>(1 + size % 7);  // from all-zero-heavy to rare zeros
    for (auto& b : in) b = (rng() % (zero_odds * 8) == 0) ? 0 : static_cast<uint8_t>(rng());
    const Bytes enc = encode(in);
    ASSERT_LE(enc.size(), np::cobs_max_encoded_size(size));
    for (uint8_t b : enc) ASSERT_NE(b, 0) << "size " << size;
    bool ok = false;
    ASSERT_EQ(decode(enc, &ok), in) << "size " << size;
    ASSERT_TRUE(ok);
  }
}

TEST(Cobs, EncodeRefusesAnOutputBufferThatMightBeTooSmall) {
  const Bytes in(10, 0x11);
  uint8_t out[10];
  EXPECT_EQ(np::cobs_encode(in.data(), in.size(), out, sizeof out), 0u);
}

TEST(Cobs, DecodeRejectsAZeroByteInsideTheInput) {
  bool ok = true;
  decode({0x03, 0x11, 0x00}, &ok);
  EXPECT_FALSE(ok);
  decode({0x00}, &ok);
  EXPECT_FALSE(ok);
}

TEST(Cobs, DecodeRejectsABlockRunningPastTheEnd) {
  bool ok = true;
  decode({0x05, 0x11, 0x22}, &ok);
  EXPECT_FALSE(ok);
}

TEST(Cobs, DecodeRefusesToWritePastTheOutputCapacity) {
  const Bytes enc = encode(Bytes(50, 0x22));
  uint8_t out[49];
  EXPECT_FALSE(np::cobs_decode(enc.data(), enc.size(), out, sizeof out).ok);
}

}  // namespace
