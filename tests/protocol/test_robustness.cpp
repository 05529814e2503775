// Bounded in-suite fuzzing: random and mutated input through the decoder.
// The libFuzzer target (protocol/fuzz) explores further; this keeps the
// basic guarantees checked on every build: no crash, every frame either
// decoded or rejected with a reason, counters that add up, and every frame
// the decoder accepts is one the typed layer can unpack.

#include <gtest/gtest.h>

#include <random>

#include "protocol/messages.hpp"
#include "protocol/host/golden_reader.hpp"
#include "protocol/host/message_text.hpp"
#include "test_util.hpp"

namespace np = nlsoft::protocol;
using namespace nlsoft::protocol::test;
using Kind = np::DecodeResult::Kind;

namespace {

struct Tally {
  uint64_t frames = 0;
  uint64_t errors = 0;
};

// Feeds everything in random-sized chunks and checks each event.
Tally run(np::Decoder& d, const Bytes& input, std::mt19937& rng) {
  Tally t;
  size_t pos = 0;
  while (pos < input.size()) {
    const size_t avail = std::min<size_t>(input.size() - pos, 1 + rng() % 97);
    np::DecodeResult r;
    const size_t used = d.feed(input.data() + pos, avail, r);
    EXPECT_GE(used, 1u);
    EXPECT_LE(used, avail);
    pos += used;
    if (r.kind == Kind::Frame) {
      ++t.frames;
      EXPECT_LE(r.frame.payload_size(), np::kMaxPayload);
      const bool known = np::with_message_type(r.frame.header.type, [&](auto msg) {
        EXPECT_EQ(np::unpack(r.frame, msg), np::StatusCode::Ok)
            << np::message_name(r.frame.header.type);
      });
      EXPECT_TRUE(known);
      // The text form must cope with anything the decoder lets through.
      EXPECT_FALSE(np::text::format_frame(r.frame).empty());
    } else if (r.kind == Kind::Error) {
      ++t.errors;
      EXPECT_NE(r.error, np::FrameError::None);
    } else {
      EXPECT_EQ(used, avail);  // no event means all offered bytes were taken
    }
  }
  return t;
}

void expect_counters_add_up(const np::Decoder& d, const Tally& t, size_t bytes) {
  EXPECT_EQ(d.stats().frames_ok, t.frames);
  EXPECT_EQ(d.stats().error_total(), t.errors);
  EXPECT_EQ(d.stats().errors[0], 0u);
  EXPECT_EQ(d.stats().bytes, bytes);
}

TEST(DecoderRobustness, TwoHundredThousandRandomBytes) {
  std::mt19937 rng(20240601);
  Bytes input(200000);
  for (auto& b : input) {
    // Zeros often enough that short "frames" of every length occur.
    b = (rng() % 40 == 0) ? 0 : static_cast<uint8_t>(rng());
  }
  np::Decoder d;
  const Tally t = run(d, input, rng);
  expect_counters_add_up(d, t, input.size());
  EXPECT_GT(t.errors, 1000u);
}

TEST(DecoderRobustness, MutatedGoldenVectors) {
  std::vector<np::golden::Vector> vectors;
  std::string error;
  ASSERT_TRUE(np::golden::read_file(NLSOFT_GOLDEN_VECTORS, vectors, error)) << error;
  std::mt19937 rng(7);
  Bytes input;
  while (input.size() < 200000) {
    Bytes w = vectors[rng() % vectors.size()].wire;
    switch (rng() % 6) {
      case 0:  // flip one bit
        w[rng() % w.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
        break;
      case 1:  // overwrite a byte
        w[rng() % w.size()] = static_cast<uint8_t>(rng());
        break;
      case 2:  // lose a byte
        w.erase(w.begin() + static_cast<long>(rng() % w.size()));
        break;
      case 3:  // duplicate a byte
        {
          const size_t i = rng() % w.size();
          w.insert(w.begin() + static_cast<long>(i), w[i]);
        }
        break;
      case 4:  // cut short
        w.resize(rng() % w.size());
        break;
      default:  // leave intact
        break;
    }
    input.insert(input.end(), w.begin(), w.end());
  }
  np::Decoder d;
  const Tally t = run(d, input, rng);
  expect_counters_add_up(d, t, input.size());
  EXPECT_GT(t.frames, 100u);
  EXPECT_GT(t.errors, 100u);
}

TEST(DecoderRobustness, SingleBitFlipsInAGoodFrameAreNeverAcceptedAsADifferentFrame) {
  np::Telemetry tel;
  tel.mask = np::telemetry_field::kAll;
  tel.n = 3;
  tel.m = 6;
  tel.cost = 3.0f;
  const Bytes good = wire_of(tel, 5);
  const auto reference = decode_all(good);
  ASSERT_EQ(reference.size(), 1u);
  for (size_t i = 0; i + 1 < good.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      Bytes w = good;
      w[i] ^= static_cast<uint8_t>(1u << bit);
      for (const Event& e : decode_all(w)) {
        if (e.kind != Kind::Frame) continue;
        EXPECT_EQ(e.payload, reference[0].payload) << "byte " << i << " bit " << bit;
      }
    }
  }
}

}  // namespace
