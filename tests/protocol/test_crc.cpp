#include <gtest/gtest.h>

#include <cstring>

#include "protocol/catalog.hpp"
#include "protocol/crc.hpp"

namespace np = nlsoft::protocol;

namespace {

const uint8_t kCheckInput[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};

TEST(Crc16, MatchesTheCcittFalseCatalogueCheckValue) {
  EXPECT_EQ(np::crc16(kCheckInput, sizeof kCheckInput), 0x29B1);
}

TEST(Crc16, OfNothingIsTheInitialValue) { EXPECT_EQ(np::crc16(nullptr, 0), 0xFFFF); }

TEST(Crc16, SplitComputationEqualsOneShot) {
  const uint16_t first = np::crc16(kCheckInput, 4);
  EXPECT_EQ(np::crc16(kCheckInput + 4, 5, first), 0x29B1);
}

TEST(Crc16, StringFormEqualsByteForm) { EXPECT_EQ(np::crc16_str("123456789"), 0x29B1); }

TEST(Crc32, MatchesTheZlibCheckValue) {
  EXPECT_EQ(np::crc32(kCheckInput, sizeof kCheckInput), 0xCBF43926u);
}

TEST(Crc32, OfNothingIsZero) { EXPECT_EQ(np::crc32(nullptr, 0), 0u); }

TEST(Crc32, ChunkedUpdatesEqualOneShot) {
  uint8_t data[1000];
  for (size_t i = 0; i < sizeof data; ++i) data[i] = static_cast<uint8_t>(i * 31 + 7);
  np::Crc32 c;
  for (size_t pos = 0; pos < sizeof data; pos += 241) {
    const size_t n = std::min<size_t>(241, sizeof data - pos);
    c.update(data + pos, n);
  }
  EXPECT_EQ(c.value(), np::crc32(data, sizeof data));
  c.reset();
  EXPECT_EQ(c.value(), 0u);
}

TEST(CrcExtra, IsDerivedFromEachTypesLayoutSignature) {
  for (const np::MsgInfo& m : np::kMessages) {
    const uint16_t c = np::crc16_str(m.signature);
    EXPECT_EQ(np::crc_extra(static_cast<uint8_t>(m.type)),
              static_cast<uint8_t>((c & 0xFF) ^ (c >> 8)))
        << m.name;
  }
}

TEST(CrcExtra, SignatureStartsWithTheMessageName) {
  for (const np::MsgInfo& m : np::kMessages) {
    const size_t n = std::strlen(m.name);
    EXPECT_EQ(std::strncmp(m.signature, m.name, n), 0) << m.name;
    EXPECT_EQ(m.signature[n], ':') << m.name;
  }
}

}  // namespace
