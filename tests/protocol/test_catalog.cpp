// The catalogue's reply column (section 6) and the golden model file
// (section 9.4), read by the library.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "protocol/catalog.hpp"
#include "shared/capacity.hpp"
#include "shared/model_file.hpp"

namespace np = nlsoft::protocol;

namespace {

uint8_t t(np::MsgType m) { return static_cast<uint8_t>(m); }

TEST(Catalog, EachRequestIsAnsweredByItsReplyOrNack) {
  using T = np::MsgType;
  const std::pair<T, T> table[] = {
      {T::Ping, T::Pong},           {T::InfoGet, T::InfoEx},       {T::ParamList, T::ParamDesc},
      {T::ParamGet, T::ParamValue}, {T::ParamSet, T::ParamValue},  {T::RefSelect, T::Ack},
      {T::XferBegin, T::XferAck},   {T::XferChunk, T::XferAck},    {T::XferCommit, T::Ack},
      {T::XferAbort, T::Ack},       {T::RunStart, T::Ack},         {T::RunStop, T::Ack},
      {T::RunHold, T::Ack},         {T::TelemetryConfig, T::Ack},  {T::StatusGet, T::Status},
      {T::RigGet, T::RigInfo},      {T::IdentStart, T::Ack},       {T::DeviceGet, T::DeviceStatus},
      {T::Settings, T::Ack},        {T::SensorStream, T::Ack},
  };
  size_t requests = 0;
  for (const np::MsgInfo& m : np::kMessages) requests += m.is_request ? 1 : 0;
  EXPECT_EQ(requests, sizeof table / sizeof table[0]);
  for (const auto& [req, rep] : table) {
    SCOPED_TRACE(np::message_name(t(req)));
    EXPECT_TRUE(np::answers(t(req), t(rep)));
    EXPECT_TRUE(np::answers(t(req), t(T::Nack)));
    // No other reply type answers it: a stray reply is never taken.
    for (const np::MsgInfo& m : np::kMessages) {
      if (m.is_request || m.type == rep || m.type == T::Nack) continue;
      if (req == T::InfoGet && m.type == T::Info) continue;
      EXPECT_FALSE(np::answers(t(req), t(m.type))) << np::message_name(t(m.type));
    }
  }
  // A 1.0 firmware answers INFO_GET with INFO.
  EXPECT_TRUE(np::answers(t(T::InfoGet), t(T::Info)));
  // A firmware-to-console type sent to the firmware is NACKed, never answered otherwise.
  EXPECT_TRUE(np::answers(t(T::Ack), t(T::Nack)));
  EXPECT_FALSE(np::answers(t(T::Ack), t(T::Ack)));
  EXPECT_FALSE(np::answers(0x3E, t(T::Nack)));
}

std::vector<uint8_t> golden_model(uint32_t& crc) {
  std::ifstream in(NLSOFT_GOLDEN_MODEL);
  EXPECT_TRUE(in.good()) << NLSOFT_GOLDEN_MODEL;
  std::vector<uint8_t> file;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("crc32:", 0) == 0) crc = uint32_t(std::stoul(line.substr(6), nullptr, 16));
    if (line.rfind("file:", 0) != 0) continue;
    std::istringstream hex(line.substr(5));
    std::string b;
    while (hex >> b) file.push_back(uint8_t(std::stoul(b, nullptr, 16)));
  }
  return file;
}

TEST(GoldenModel, ParsesAsTheSpecSaysAndItsTrailerIsTheHash) {
  uint32_t crc = 0;
  std::vector<uint8_t> file = golden_model(crc);
  ASSERT_EQ(file.size(), 96u);
  nlsoft::Model<nlsoft::HostCapacity> m;
  alignas(4) uint8_t copy[96];
  std::copy(file.begin(), file.end(), copy);
  ASSERT_EQ(nlsoft::parse_model(copy, sizeof copy, m, nullptr, 0), nlsoft::Status::Ok);
  EXPECT_EQ(m.hash, crc);
  EXPECT_EQ(m.m, 1);
  EXPECT_EQ(m.n, 1);
  EXPECT_EQ(m.nd, 2);
  EXPECT_EQ(m.dd, 2);
  EXPECT_EQ(m.layer_count, 1);
  EXPECT_EQ(m.param_count, 15u);
  EXPECT_FLOAT_EQ(m.weights(m.layer[0])[2], 1.8f);
  copy[40] ^= 0x10;  // a parameter byte: the trailer no longer matches
  EXPECT_EQ(nlsoft::parse_model(copy, sizeof copy, m, nullptr, 0), nlsoft::Status::BadChecksum);
}

}  // namespace
