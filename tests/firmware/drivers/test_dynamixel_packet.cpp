// The Dynamixel packet layer against the ROBOTIS manuals' example packets
// (dynamixel_vectors.txt), then the parser against what a half-duplex line
// delivers: garbage, packets cut short, corrupted, from other servos, its
// own echo, too long for it.
#include "firmware/drivers/dynamixel_packet.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace nlsoft::fw::drivers::dynamixel {
namespace {

using Bytes = std::vector<uint8_t>;

struct Vector {
  int protocol;
  Bytes bytes;
};

std::map<std::string, Vector> load_vectors() {
  std::ifstream in(NLSOFT_DYNAMIXEL_VECTORS);
  std::map<std::string, Vector> out;
  std::string line;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find('#'));
    std::istringstream fields(line);
    std::string name;
    Vector v{};
    if (!(fields >> name)) continue;
    fields >> v.protocol;
    std::string hex;
    while (fields >> hex) v.bytes.push_back(static_cast<uint8_t>(std::stoul(hex, nullptr, 16)));
    out[name] = v;
  }
  return out;
}

const std::map<std::string, Vector>& vectors() {
  static const std::map<std::string, Vector> v = load_vectors();
  return v;
}

const Bytes& vec(const std::string& name) {
  const auto it = vectors().find(name);
  EXPECT_NE(it, vectors().end()) << name;
  static const Bytes none;
  return it == vectors().end() ? none : it->second.bytes;
}

// How each instruction vector is built, from the conditions the manual
// states beside it.
using Build = std::function<Encoded(uint8_t*, size_t)>;

std::map<std::string, Build> instruction_builders() {
  std::map<std::string, Build> b;
  b["p1_checksum_example"] = [](uint8_t* o, size_t c) {
    const uint8_t data[] = {0x64, 0xAA};
    return p1::write(1, 0x0C, data, 2, o, c);
  };
  b["p1_ping"] = [](uint8_t* o, size_t c) { return p1::ping(1, o, c); };
  b["p1_read"] = [](uint8_t* o, size_t c) { return p1::read(1, 43, 1, o, c); };
  b["p1_write"] = [](uint8_t* o, size_t c) {
    const uint8_t one = 1;
    return p1::write(kBroadcastId, 3, &one, 1, o, c);
  };
  b["p1_reg_write"] = [](uint8_t* o, size_t c) {
    uint8_t p[3] = {30};
    store_le16(p + 1, 500);
    return p1::instruction(1, static_cast<uint8_t>(Instruction::kRegWrite), p, 3, o, c);
  };
  b["p1_action"] = [](uint8_t* o, size_t c) {
    return p1::instruction(kBroadcastId, static_cast<uint8_t>(Instruction::kAction), nullptr, 0, o, c);
  };
  b["p1_factory_reset"] = [](uint8_t* o, size_t c) {
    return p1::instruction(0, static_cast<uint8_t>(Instruction::kFactoryReset), nullptr, 0, o, c);
  };
  b["p1_sync_write_2"] = [](uint8_t* o, size_t c) {
    // Goal Position (30) and Moving Speed (32): id 0 0x010, 0x150; id 1 0x220, 0x360.
    uint8_t d[2][4];
    const uint16_t values[2][2] = {{0x010, 0x150}, {0x220, 0x360}};
    for (int i = 0; i < 2; ++i) {
      store_le16(d[i], values[i][0]);
      store_le16(d[i] + 2, values[i][1]);
    }
    const SyncTarget t[] = {{0, d[0]}, {1, d[1]}};
    return p1::sync_write(30, 4, t, 2, o, c);
  };
  b["p1_sync_write_4"] = [](uint8_t* o, size_t c) {
    uint8_t d[4][4];
    const uint16_t values[4][2] = {{0x010, 0x150}, {0x220, 0x360}, {0x030, 0x170}, {0x220, 0x380}};
    for (int i = 0; i < 4; ++i) {
      store_le16(d[i], values[i][0]);
      store_le16(d[i] + 2, values[i][1]);
    }
    const SyncTarget t[] = {{0, d[0]}, {1, d[1]}, {2, d[2]}, {3, d[3]}};
    return p1::sync_write(30, 4, t, 4, o, c);
  };
  b["p2_ping"] = [](uint8_t* o, size_t c) { return p2::ping(1, o, c); };
  b["p2_ping_broadcast"] = [](uint8_t* o, size_t c) { return p2::ping(kBroadcastId, o, c); };
  b["p2_read"] = [](uint8_t* o, size_t c) { return p2::read(1, 132, 4, o, c); };
  b["p2_write"] = [](uint8_t* o, size_t c) {
    uint8_t d[4];
    store_le32(d, 512);
    return p2::write(1, 116, d, 4, o, c);
  };
  b["p2_reg_write"] = [](uint8_t* o, size_t c) {
    uint8_t p[6];
    store_le16(p, 104);
    store_le32(p + 2, 200);
    return p2::instruction(1, static_cast<uint8_t>(Instruction::kRegWrite), p, 6, o, c);
  };
  b["p2_action"] = [](uint8_t* o, size_t c) {
    return p2::instruction(1, static_cast<uint8_t>(Instruction::kAction), nullptr, 0, o, c);
  };
  b["p2_factory_reset"] = [](uint8_t* o, size_t c) {
    const uint8_t option = 0x01;
    return p2::instruction(1, static_cast<uint8_t>(Instruction::kFactoryReset), &option, 1, o, c);
  };
  b["p2_reboot"] = [](uint8_t* o, size_t c) {
    return p2::instruction(1, static_cast<uint8_t>(Instruction::kReboot), nullptr, 0, o, c);
  };
  b["p2_clear"] = [](uint8_t* o, size_t c) {
    const uint8_t p[] = {0x01, 0x44, 0x58, 0x4C, 0x22};
    return p2::instruction(1, 0x10, p, 5, o, c);
  };
  b["p2_sync_read"] = [](uint8_t* o, size_t c) {
    uint8_t p[6];
    store_le16(p, 132);
    store_le16(p + 2, 4);
    p[4] = 1;
    p[5] = 2;
    return p2::instruction(kBroadcastId, static_cast<uint8_t>(Instruction::kSyncRead), p, 6, o, c);
  };
  b["p2_sync_write"] = [](uint8_t* o, size_t c) {
    uint8_t d[2][4];
    store_le32(d[0], 150);
    store_le32(d[1], 170);
    const SyncTarget t[] = {{1, d[0]}, {2, d[1]}};
    return p2::sync_write(116, 4, t, 2, o, c);
  };
  b["p2_bulk_write"] = [](uint8_t* o, size_t c) {
    const uint8_t p[] = {0x01, 0x20, 0x00, 0x02, 0x00, 0xA0, 0x00, 0x02, 0x1F, 0x00, 0x01, 0x00, 0x50};
    return p2::instruction(kBroadcastId, 0x93, p, sizeof p, o, c);
  };
  b["p2_write_stuffed"] = [](uint8_t* o, size_t c) {
    uint8_t d[4];
    store_le32(d, static_cast<uint32_t>(-131073));
    return p2::write(1, 116, d, 4, o, c);
  };
  return b;
}

// What each status vector carries, from the manual's conditions.
struct StatusExpect {
  uint8_t id;
  uint8_t error;
  Bytes params;
};

const std::map<std::string, StatusExpect>& status_expectations() {
  static const std::map<std::string, StatusExpect> e = {
      {"p1_ping_status", {1, 0, {}}},
      {"p1_read_status", {1, 0, {0x20}}},
      {"p1_error_status", {1, 0x24, {}}},
      {"p1_factory_reset_status", {0, 0, {}}},
      {"p1_bulk_read_status_1", {1, 0, {0x00, 0x80}}},
      {"p1_bulk_read_status_2", {2, 0, {0x00, 0x80}}},
      {"p2_ping_status", {1, 0, {0x06, 0x04, 0x26}}},
      {"p2_ping_status_2", {2, 0, {0x06, 0x04, 0x26}}},
      {"p2_read_status", {1, 0, {0xA6, 0x00, 0x00, 0x00}}},
      {"p2_write_status", {1, 0, {}}},
      {"p2_sync_read_status_2", {2, 0, {0x1F, 0x08, 0x00, 0x00}}},
      {"p2_bulk_read_status_1", {1, 0, {0x77, 0x00}}},
      {"p2_bulk_read_status_2", {2, 0, {0x24}}},
      {"p2_read_status_stuffed", {1, 0, {0xFF, 0xFF, 0xFD, 0xFF}}},
  };
  return e;
}

Protocol protocol_of(const std::string& name) { return vectors().at(name).protocol == 1 ? Protocol::k1 : Protocol::k2; }

// Both parsers, sized for the longest packet any vector has (the
// four-servo SYNC_WRITE's 22 parameters).
struct AnyParser {
  StatusParser1<32> v1;
  StatusParser2<32> v2;
  StatusParser& of(Protocol p) { return p == Protocol::k1 ? static_cast<StatusParser&>(v1) : v2; }
};

// An event and what the parser showed with it.
struct Seen {
  ParseEvent event;
  uint8_t id;
  uint8_t error;
  Bytes params;
};

// Feeds bytes one at a time, draining what a rescan leaves pending after
// each event, as the firmware will.
std::vector<Seen> feed_all(StatusParser& p, const Bytes& bytes) {
  std::vector<Seen> seen;
  auto record = [&](ParseEvent e) {
    seen.push_back({e, p.id(), p.error(), Bytes(p.params(), p.params() + p.param_count())});
  };
  for (uint8_t b : bytes) {
    ParseEvent e = p.feed(b);
    while (e != ParseEvent::kNone) {
      record(e);
      e = p.pending() ? p.poll() : ParseEvent::kNone;
    }
  }
  return seen;
}

// Then the line goes quiet: give up what is unfinished and rescan it,
// until nothing is left.
std::vector<Seen> feed_then_idle(StatusParser& p, const Bytes& bytes) {
  std::vector<Seen> seen = feed_all(p, bytes);
  for (ParseEvent e = p.idle(); e != ParseEvent::kNone; e = p.idle()) {
    while (e != ParseEvent::kNone) {
      seen.push_back({e, p.id(), p.error(), Bytes(p.params(), p.params() + p.param_count())});
      e = p.pending() ? p.poll() : ParseEvent::kNone;
    }
  }
  return seen;
}

size_t count(const std::vector<Seen>& seen, ParseEvent e) {
  size_t n = 0;
  for (const Seen& s : seen) n += s.event == e;
  return n;
}

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

void expect_status(const Seen& s, const StatusExpect& want, const std::string& what) {
  EXPECT_EQ(s.event, ParseEvent::kComplete) << what;
  EXPECT_EQ(s.id, want.id) << what;
  EXPECT_EQ(s.error, want.error) << what;
  EXPECT_EQ(s.params, want.params) << what;
}

// ------------------------------------------------------------ vectors ----

TEST(DynamixelVectors, EveryPacketIsNamedAndSoundAndEveryNameHasAPacket) {
  ASSERT_GE(vectors().size(), 30u) << NLSOFT_DYNAMIXEL_VECTORS;
  const auto builders = instruction_builders();
  std::set<std::string> known;
  for (const auto& [name, build] : builders) known.insert(name);
  for (const auto& [name, e] : status_expectations()) EXPECT_TRUE(known.insert(name).second) << name;
  for (const auto& [name, v] : vectors()) {
    EXPECT_EQ(known.count(name), 1u) << "no test says what " << name << " is";
    ASSERT_TRUE(v.protocol == 1 || v.protocol == 2) << name;
    const Bytes& b = v.bytes;
    if (v.protocol == 1) {
      ASSERT_GE(b.size(), 6u) << name;
      EXPECT_EQ(b[3], b.size() - 4) << name;
      EXPECT_EQ(p1::checksum(b.data() + 2, b.size() - 3), b.back()) << name;
    } else {
      ASSERT_GE(b.size(), 10u) << name;
      EXPECT_EQ(b[5] | b[6] << 8, static_cast<int>(b.size() - 7)) << name;
      EXPECT_EQ(p2::crc16(0, b.data(), b.size() - 2), b[b.size() - 2] | b[b.size() - 1] << 8) << name;
    }
  }
  for (const std::string& name : known) EXPECT_EQ(vectors().count(name), 1u) << name << " missing from the file";
}

TEST(DynamixelCrc, IsRobotisUpdateCrcAndContinues) {
  // The e-manual's Ping example: CRC 0x4E19 over header to instruction.
  const Bytes& ping = vec("p2_ping");
  EXPECT_EQ(p2::crc16(0, ping.data(), 8), 0x4E19);
  // Computed in two pieces, the same.
  EXPECT_EQ(p2::crc16(p2::crc16(0, ping.data(), 3), ping.data() + 3, 5), 0x4E19);
  // The bitwise definition: polynomial 0x8005, MSB first, initial 0.
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    Bytes data(static_cast<size_t>(rng() % 40));
    for (uint8_t& b : data) b = static_cast<uint8_t>(rng());
    unsigned crc = 0;
    for (uint8_t b : data) {
      crc ^= unsigned{b} << 8;
      for (int i = 0; i < 8; ++i) crc = (crc & 0x8000) ? ((crc << 1) ^ 0x8005) & 0xFFFF : (crc << 1) & 0xFFFF;
    }
    EXPECT_EQ(p2::crc16(0, data.data(), data.size()), crc);
  }
}

// ----------------------------------------------------------- encoding ----

TEST(DynamixelEncode, EveryInstructionVectorByteForByte) {
  for (const auto& [name, build] : instruction_builders()) {
    const Bytes& want = vec(name);
    uint8_t out[80];
    std::memset(out, 0xA5, sizeof out);
    const Encoded e = build(out, sizeof out);
    ASSERT_TRUE(e.ok()) << name;
    EXPECT_EQ(Bytes(out, out + e.length), want) << name;
    EXPECT_EQ(out[e.length], 0xA5) << name << ": wrote past its length";
  }
}

TEST(DynamixelEncode, EveryStatusVectorByteForByte) {
  for (const auto& [name, want] : status_expectations()) {
    uint8_t out[40];
    const Encoded e = protocol_of(name) == Protocol::k1
                          ? p1::status(want.id, want.error, want.params.data(), want.params.size(), out, sizeof out)
                          : p2::status(want.id, want.error, want.params.data(), want.params.size(), out, sizeof out);
    ASSERT_TRUE(e.ok()) << name;
    EXPECT_EQ(Bytes(out, out + e.length), vec(name)) << name;
  }
}

TEST(DynamixelEncode, EveryEncoderRefusesOneByteTooFewAndWritesNothingPastIt) {
  std::map<std::string, Build> all = instruction_builders();
  for (const auto& [name, want] : status_expectations()) {
    const StatusExpect w = want;
    all[name] = [w, p = protocol_of(name)](uint8_t* o, size_t c) {
      return p == Protocol::k1 ? p1::status(w.id, w.error, w.params.data(), w.params.size(), o, c)
                               : p2::status(w.id, w.error, w.params.data(), w.params.size(), o, c);
    };
  }
  for (const auto& [name, build] : all) {
    const size_t size = vec(name).size();
    for (size_t capacity = 0; capacity < size; ++capacity) {
      uint8_t out[80];
      std::memset(out, 0xA5, sizeof out);
      const Encoded e = build(out, capacity);
      EXPECT_EQ(e.status, EncodeStatus::kOverflow) << name << " in " << capacity;
      EXPECT_EQ(e.length, 0u) << name;
      for (size_t i = capacity; i < sizeof out; ++i) ASSERT_EQ(out[i], 0xA5) << name << " in " << capacity << " at " << i;
    }
    uint8_t out[80];
    EXPECT_TRUE(build(out, size).ok()) << name << ": its exact size is enough";
  }
}

TEST(DynamixelEncode, RefusesWhatTheProtocolsCannotSay) {
  uint8_t out[600];
  const uint8_t data[4] = {1, 2, 3, 4};
  const auto bad = [](Encoded e) { return e.status == EncodeStatus::kBadArgument && e.length == 0; };
  // 1.0: 0xFF is no id; LEN is a byte; zero bytes to read or write; null pointers.
  EXPECT_TRUE(bad(p1::ping(0xFF, out, sizeof out)));
  EXPECT_TRUE(bad(p1::ping(1, nullptr, sizeof out)));
  EXPECT_TRUE(bad(p1::read(1, 36, 0, out, sizeof out)));
  EXPECT_TRUE(bad(p1::write(1, 30, data, 0, out, sizeof out)));
  EXPECT_TRUE(bad(p1::write(1, 30, nullptr, 2, out, sizeof out)));
  EXPECT_TRUE(bad(p1::instruction(1, 0x04, nullptr, 3, out, sizeof out)));
  Bytes many(254, 0);
  EXPECT_TRUE(bad(p1::instruction(1, 0x04, many.data(), 254, out, sizeof out)));
  EXPECT_TRUE(p1::instruction(1, 0x04, many.data(), 253, out, sizeof out).ok());
  EXPECT_TRUE(bad(p1::write(1, 0, many.data(), 253, out, sizeof out)));
  EXPECT_TRUE(p1::write(1, 0, many.data(), 252, out, sizeof out).ok());
  EXPECT_TRUE(bad(p1::status(kBroadcastId, 0, nullptr, 0, out, sizeof out)));
  // 1.0 SYNC_WRITE: (L + 1) * N + 4 <= 255, servo ids 0..0xFD, something to write.
  std::vector<SyncTarget> targets;
  for (uint8_t id = 0; id < 60; ++id) targets.push_back({id, data});
  EXPECT_TRUE(p1::sync_write(30, 4, targets.data(), 50, out, sizeof out).ok());  // 254
  EXPECT_TRUE(bad(p1::sync_write(30, 4, targets.data(), 51, out, sizeof out)));  // 259
  EXPECT_TRUE(bad(p1::sync_write(30, 0, targets.data(), 2, out, sizeof out)));
  EXPECT_TRUE(bad(p1::sync_write(30, 4, targets.data(), 0, out, sizeof out)));
  EXPECT_TRUE(bad(p1::sync_write(30, 4, nullptr, 2, out, sizeof out)));
  SyncTarget broadcast_in_list[] = {{1, data}, {kBroadcastId, data}};
  EXPECT_TRUE(bad(p1::sync_write(30, 4, broadcast_in_list, 2, out, sizeof out)));
  SyncTarget null_data[] = {{1, data}, {2, nullptr}};
  EXPECT_TRUE(bad(p1::sync_write(30, 4, null_data, 2, out, sizeof out)));
  // 2.0 reserves 0xFD and 0xFF; servos are 0..0xFC.
  EXPECT_TRUE(bad(p2::ping(0xFD, out, sizeof out)));
  EXPECT_TRUE(bad(p2::ping(0xFF, out, sizeof out)));
  EXPECT_TRUE(p2::ping(0xFC, out, sizeof out).ok());
  EXPECT_TRUE(bad(p2::read(1, 132, 0, out, sizeof out)));
  EXPECT_TRUE(bad(p2::write(1, 116, data, 0, out, sizeof out)));
  EXPECT_TRUE(bad(p2::write(1, 116, nullptr, 4, nullptr, sizeof out)));
  EXPECT_TRUE(bad(p2::status(kBroadcastId, 0, nullptr, 0, out, sizeof out)));
  EXPECT_TRUE(bad(p2::sync_write(116, 4, broadcast_in_list, 2, out, sizeof out)));
  SyncTarget reserved[] = {{0xFD, data}};
  EXPECT_TRUE(bad(p2::sync_write(116, 4, reserved, 1, out, sizeof out)));
  EXPECT_TRUE(bad(p2::sync_write(116, 0, targets.data(), 2, out, sizeof out)));
  EXPECT_TRUE(bad(p2::sync_write(116, 4, targets.data(), 0, out, sizeof out)));
}

TEST(DynamixelEncode, SyncWriteLengthFieldsFollowTheFormulas) {
  uint8_t d[8][2] = {};
  SyncTarget t[8];
  for (uint8_t i = 0; i < 8; ++i) t[i] = {i, d[i]};
  uint8_t out[128];
  for (size_t n = 1; n <= 8; ++n) {
    const Encoded e1 = p1::sync_write(30, 2, t, n, out, sizeof out);
    ASSERT_TRUE(e1.ok());
    EXPECT_EQ(out[3], (2 + 1) * n + 4);  // the manual's ((L + 1) * N) + 4
    EXPECT_EQ(e1.length, out[3] + 4u);
    const Encoded e2 = p2::sync_write(30, 2, t, n, out, sizeof out);
    ASSERT_TRUE(e2.ok());
    EXPECT_EQ(out[5] | out[6] << 8, static_cast<int>((2 + 1) * n + 4 + 3));  // parameters + instruction + CRC
    EXPECT_EQ(e2.length, p2::kOverhead + 4 + 3 * n);
  }
}

// ------------------------------------------------------------ parsing ----

TEST(DynamixelParse, EveryStatusVectorOneByteAtATime) {
  for (const auto& [name, want] : status_expectations()) {
    AnyParser parsers;
    StatusParser& p = parsers.of(protocol_of(name));
    p.expect(want.id);
    const Bytes& b = vec(name);
    for (size_t i = 0; i + 1 < b.size(); ++i) ASSERT_EQ(p.feed(b[i]), ParseEvent::kNone) << name << " at " << i;
    ASSERT_EQ(p.feed(b.back()), ParseEvent::kComplete) << name;
    expect_status({ParseEvent::kComplete, p.id(), p.error(), Bytes(p.params(), p.params() + p.param_count())}, want,
                  name);
    EXPECT_FALSE(p.pending()) << name;
  }
}

TEST(DynamixelParse, InstructionVectorsParseBack) {
  // 1.0 has one layout for both directions: an instruction reads as a
  // "status" whose error byte is the instruction. 2.0 tells them apart: an
  // instruction (the line's echo of what was sent) is skipped as such.
  for (const auto& [name, build] : instruction_builders()) {
    const Bytes& b = vec(name);
    AnyParser parsers;
    StatusParser& p = parsers.of(protocol_of(name));
    const std::vector<Seen> seen = feed_all(p, b);
    ASSERT_EQ(seen.size(), 1u) << name;
    if (protocol_of(name) == Protocol::k1) {
      EXPECT_EQ(seen[0].event, ParseEvent::kComplete) << name;
      EXPECT_EQ(seen[0].id, b[2]) << name;
      EXPECT_EQ(seen[0].error, b[4]) << name;
      EXPECT_EQ(seen[0].params, Bytes(b.begin() + 5, b.end() - 1)) << name;
    } else {
      EXPECT_EQ(seen[0].event, ParseEvent::kNotStatus) << name;
      EXPECT_EQ(seen[0].id, b[4]) << name;
    }
  }
}

TEST(DynamixelParse, GarbageBeforeAStatusIsSkipped) {
  // Header fragments, a false length, noise: each before every status vector.
  const std::vector<Bytes> garbage = {
      {0x00, 0x13, 0x37},
      {0xFF},
      {0xFF, 0xFF},
      {0xFF, 0xFF, 0xFF},
      {0xFF, 0xFF, 0xFD},
      {0xFF, 0xFF, 0xFD, 0x00},
      {0xFF, 0xFF, 0xFD, 0x00, 0x01},
      {0xFF, 0xFF, 0x01},
      {0x55, 0xFF, 0x00, 0xFF, 0xFF, 0xFD, 0xFD, 0x12},
  };
  for (const auto& [name, want] : status_expectations()) {
    for (size_t g = 0; g < garbage.size(); ++g) {
      AnyParser parsers;
      StatusParser& p = parsers.of(protocol_of(name));
      p.expect(want.id);
      const std::vector<Seen> seen = feed_all(p, cat({garbage[g], vec(name)}));
      ASSERT_FALSE(seen.empty()) << name << " after garbage " << g;
      EXPECT_EQ(count(seen, ParseEvent::kComplete), 1u) << name << " after garbage " << g;
      expect_status(seen.back(), want, name + " after garbage " + std::to_string(g));
      // Noise and header fragments that never reach a length field raise
      // no event at all (1.0's id byte 0xFD with the 0xFF after it does:
      // a length of 255).
      const size_t silent = protocol_of(name) == Protocol::k1 ? 4 : 6;
      if (g < silent) {
        EXPECT_EQ(seen.size(), 1u) << name << " after garbage " << g;
      }
    }
  }
}

TEST(DynamixelParse, SplitAtEveryPositionWithPollsBetween) {
  for (const auto& [name, want] : status_expectations()) {
    const Bytes& b = vec(name);
    for (size_t split = 1; split < b.size(); ++split) {
      AnyParser parsers;
      StatusParser& p = parsers.of(protocol_of(name));
      std::vector<Seen> seen = feed_all(p, Bytes(b.begin(), b.begin() + split));
      EXPECT_TRUE(seen.empty()) << name << " split at " << split;
      EXPECT_EQ(p.poll(), ParseEvent::kNone);  // nothing pending: a poll changes nothing
      seen = feed_all(p, Bytes(b.begin() + split, b.end()));
      ASSERT_EQ(seen.size(), 1u) << name << " split at " << split;
      expect_status(seen[0], want, name + " split at " + std::to_string(split));
    }
  }
}

TEST(DynamixelParse, APacketCutShortAtEveryPositionDoesNotTakeTheNextOne) {
  for (const auto& [name, want] : status_expectations()) {
    const Bytes& b = vec(name);
    for (size_t cut = 1; cut < b.size(); ++cut) {
      AnyParser parsers;
      StatusParser& p = parsers.of(protocol_of(name));
      p.expect(want.id);
      const std::vector<Seen> seen = feed_all(p, cat({Bytes(b.begin(), b.begin() + cut), b}));
      ASSERT_EQ(count(seen, ParseEvent::kComplete), 1u) << name << " cut at " << cut;
      expect_status(seen.back(), want, name + " cut at " + std::to_string(cut));
    }
  }
}

TEST(DynamixelParse, ACutPacketSwallowingAWholeOneGivesItBackOnPoll) {
  // A 1.0 header whose length (10) takes in the whole ping status after it:
  // the checksum fails at the tenth byte, and the ping status, already fed,
  // is found in the rescan.
  StatusParser1<16> p;
  const Bytes cut = {0xFF, 0xFF, 0x01, 0x0A};
  const Bytes good = vec("p1_ping_status");
  const Bytes tail = {0x00, 0x00, 0x00, 0x00};
  std::vector<ParseEvent> events;
  for (uint8_t byte : cat({cut, good, tail})) {
    const ParseEvent e = p.feed(byte);
    if (e != ParseEvent::kNone) events.push_back(e);
  }
  ASSERT_EQ(events, (std::vector<ParseEvent>{ParseEvent::kBadChecksum}));
  ASSERT_TRUE(p.pending());
  EXPECT_EQ(p.poll(), ParseEvent::kComplete);
  EXPECT_EQ(p.id(), 1);
  EXPECT_EQ(p.error(), 0);
  EXPECT_EQ(p.param_count(), 0u);
  EXPECT_EQ(p.poll(), ParseEvent::kNone);
  EXPECT_FALSE(p.pending());
  // Not polling works too: the next feed goes on with the pending bytes first.
  StatusParser1<16> q;
  std::vector<ParseEvent> q_events;
  for (uint8_t byte : cat({cut, good, tail, good})) {
    const ParseEvent e = q.feed(byte);
    if (e != ParseEvent::kNone) q_events.push_back(e);
  }
  EXPECT_EQ(q_events, (std::vector<ParseEvent>{ParseEvent::kBadChecksum, ParseEvent::kComplete,
                                               ParseEvent::kComplete}));
}

TEST(DynamixelParse, ACorruptedChecksumOrCrcIsReportedAndTheNextPacketStillParses) {
  for (const auto& [name, want] : status_expectations()) {
    const Bytes& good = vec(name);
    // The checksum / CRC itself, then each byte it covers after the header.
    const size_t first = protocol_of(name) == Protocol::k1 ? 2 : 4;
    std::vector<size_t> at = {good.size() - 1};
    for (size_t i = first; i + 1 < good.size(); ++i) at.push_back(i);
    for (size_t i : at) {
      Bytes bad = good;
      bad[i] ^= 0x10;
      AnyParser parsers;
      StatusParser& p = parsers.of(protocol_of(name));
      p.expect(want.id);
      const std::vector<Seen> seen = feed_then_idle(p, cat({bad, good}));
      ASSERT_FALSE(seen.empty()) << name << " corrupt at " << i;
      EXPECT_EQ(count(seen, ParseEvent::kComplete), 1u) << name << " corrupt at " << i;
      expect_status(seen.back(), want, name + " corrupt at " + std::to_string(i));
      // A corrupted length may read as something else (too long; or, taking
      // the next packet in, cut short when the line goes quiet), a corrupted
      // stuffed byte as stuffing missing; a corrupted id, checksum, error or
      // parameter is a bad checksum.
      const bool in_length = protocol_of(name) == Protocol::k1 ? i == 3 : (i == 5 || i == 6);
      const bool stuffed = protocol_of(name) == Protocol::k2 && i >= 10 && good[i - 3] == 0xFF &&
                           good[i - 2] == 0xFF && good[i - 1] == 0xFD && good[i] == 0xFD;
      if (stuffed) {
        EXPECT_EQ(seen.front().event, ParseEvent::kMalformed) << name << " corrupt at " << i;
      } else if (!in_length) {
        EXPECT_EQ(seen.front().event, ParseEvent::kBadChecksum) << name << " corrupt at " << i;
      }
    }
  }
}

TEST(DynamixelParse, AnotherServosAnswerIsWrongId) {
  for (const auto& [name, want] : status_expectations()) {
    AnyParser parsers;
    StatusParser& p = parsers.of(protocol_of(name));
    p.expect(static_cast<uint8_t>(want.id + 1));
    std::vector<Seen> seen = feed_all(p, vec(name));
    ASSERT_EQ(seen.size(), 1u) << name;
    EXPECT_EQ(seen[0].event, ParseEvent::kWrongId) << name;
    EXPECT_EQ(seen[0].id, want.id) << name;
    // The broadcast expectation takes anyone: a broadcast PING's answers.
    p.expect(kBroadcastId);
    seen = feed_all(p, vec(name));
    ASSERT_EQ(seen.size(), 1u) << name;
    expect_status(seen[0], want, name);
  }
  StatusParser2<4> p;
  p.expect(kBroadcastId);
  const std::vector<Seen> seen = feed_all(p, cat({vec("p2_ping_status"), vec("p2_ping_status_2")}));
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].id, 1);
  EXPECT_EQ(seen[1].id, 2);
}

TEST(DynamixelParse, TheLinesEchoOfTheInstructionIsSkipped) {
  // Single-wire half duplex: the receiver hears the instruction go out, then the answer.
  StatusParser2<8> p;
  p.expect(1);
  const std::vector<Seen> seen = feed_all(p, cat({vec("p2_read"), vec("p2_read_status")}));
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].event, ParseEvent::kNotStatus);
  expect_status(seen[1], status_expectations().at("p2_read_status"), "after the echo");
  // The echo of a SYNC_WRITE longer than the parser holds: refused, then the next status.
  StatusParser2<2> small;
  const std::vector<Seen> s2 = feed_all(small, cat({vec("p2_sync_write"), vec("p2_write_status")}));
  ASSERT_FALSE(s2.empty());
  EXPECT_EQ(s2.front().event, ParseEvent::kTooLong);
  EXPECT_EQ(count(s2, ParseEvent::kComplete), 1u);
  EXPECT_EQ(s2.back().event, ParseEvent::kComplete);
}

// Storage between guard bytes, to see that nothing is written past it.
template <size_t N>
struct Guarded {
  uint8_t before[32];
  uint8_t storage[N];
  uint8_t after[32];
  Guarded() {
    std::memset(before, 0xA5, sizeof before);
    std::memset(storage, 0, sizeof storage);
    std::memset(after, 0xA5, sizeof after);
  }
  bool intact() const {
    for (size_t i = 0; i < 32; ++i)
      if (before[i] != 0xA5 || after[i] != 0xA5) return false;
    return true;
  }
};

TEST(DynamixelParse, APacketLongerThanTheParserIsRefusedWithoutOverrun) {
  for (Protocol proto : {Protocol::k1, Protocol::k2}) {
    constexpr size_t kMax = 2;
    Guarded<StatusParser::storage_size(Protocol::k2, kMax)> g;
    StatusParser p(proto, g.storage, StatusParser::storage_size(proto, kMax), kMax);
    ASSERT_EQ(p.max_params(), kMax);
    // 40 parameters of 0xFF: the longest run of header bytes there is.
    uint8_t long_packet[80];
    const Bytes ffs(40, 0xFF);
    const Encoded e = proto == Protocol::k1 ? p1::status(1, 0, ffs.data(), ffs.size(), long_packet, sizeof long_packet)
                                            : p2::status(1, 0, ffs.data(), ffs.size(), long_packet, sizeof long_packet);
    ASSERT_TRUE(e.ok());
    const Bytes fits = proto == Protocol::k1 ? vec("p1_bulk_read_status_1") : vec("p2_bulk_read_status_1");
    std::vector<Seen> seen = feed_all(p, cat({Bytes(long_packet, long_packet + e.length), fits}));
    EXPECT_TRUE(g.intact());
    ASSERT_FALSE(seen.empty());
    EXPECT_EQ(seen.front().event, ParseEvent::kTooLong);
    EXPECT_EQ(count(seen, ParseEvent::kComplete), 1u);
    EXPECT_EQ(seen.back().event, ParseEvent::kComplete);
    const size_t check = proto == Protocol::k1 ? 1 : 2;
    EXPECT_EQ(seen.back().params, (Bytes{fits.end() - check - 2, fits.end() - check}));
    // One parameter more than it holds.
    const uint8_t three[3] = {1, 2, 3};
    uint8_t out[20];
    const Encoded over = proto == Protocol::k1 ? p1::status(1, 0, three, 3, out, sizeof out)
                                               : p2::status(1, 0, three, 3, out, sizeof out);
    seen = feed_all(p, Bytes(out, out + over.length));
    ASSERT_FALSE(seen.empty());
    EXPECT_EQ(seen.front().event, ParseEvent::kTooLong);
    EXPECT_EQ(count(seen, ParseEvent::kComplete), 0u);
    EXPECT_TRUE(g.intact());
  }
  // Storage too small for its max_params: it holds fewer, and says so.
  uint8_t tiny[10];
  StatusParser p(Protocol::k1, tiny, sizeof tiny, 16);
  EXPECT_EQ(p.max_params(), 3u);  // 6 + 3 + 1 = 10
}

TEST(DynamixelParse, AStuffedPacketNeedsNoMoreRoomThanItsParametersUnstuffed) {
  // Four parameters FF FF FD FF arrive as five; a parser for four takes them.
  StatusParser2<4> p;
  const std::vector<Seen> seen = feed_all(p, vec("p2_read_status_stuffed"));
  ASSERT_EQ(seen.size(), 1u);
  expect_status(seen[0], status_expectations().at("p2_read_status_stuffed"), "stuffed");
  // Worst case: every three parameters gain a byte.
  Bytes params;
  for (int i = 0; i < 5; ++i) params.insert(params.end(), {0xFF, 0xFF, 0xFD});
  uint8_t out[64];
  const Encoded e = p2::status(3, 0, params.data(), params.size(), out, sizeof out);
  ASSERT_TRUE(e.ok());
  EXPECT_EQ(e.length, p2::max_packet_size(params.size() + 1));
  StatusParser2<15> q;
  const std::vector<Seen> s = feed_all(q, Bytes(out, out + e.length));
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].params, params);
}

TEST(DynamixelParse, AHeaderInsideA20BodyIsTheNextPacket) {
  // Stuffing keeps FF FF FD out of a 2.0 body: one not followed by the
  // stuffed FD is a new header, reported at once rather than at the CRC.
  const Bytes& status = vec("p2_ping_status");
  const Bytes cut(status.begin(), status.begin() + 9);  // header, id, length, 0x55, error
  StatusParser2<8> p;
  std::vector<ParseEvent> events;
  for (uint8_t byte : cat({cut, status})) {
    ParseEvent e = p.feed(byte);
    while (e != ParseEvent::kNone) {
      events.push_back(e);
      e = p.pending() ? p.poll() : ParseEvent::kNone;
    }
  }
  EXPECT_EQ(events, (std::vector<ParseEvent>{ParseEvent::kMalformed, ParseEvent::kComplete}));
}

TEST(DynamixelParse, LengthFieldsTooShortAreMalformed) {
  StatusParser1<8> p1p;
  const Bytes short1 = {0xFF, 0xFF, 0x01, 0x01, 0xFD};
  std::vector<Seen> seen = feed_all(p1p, cat({short1, vec("p1_ping_status")}));
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.front().event, ParseEvent::kMalformed);
  EXPECT_EQ(seen.back().event, ParseEvent::kComplete);
  // 2.0: a status of LEN 3 (instruction and CRC only) has no error byte.
  StatusParser2<8> p2p;
  uint8_t out[16];
  const Encoded e = p2::instruction(1, 0x55, nullptr, 0, out, sizeof out);
  ASSERT_TRUE(e.ok());
  seen = feed_all(p2p, Bytes(out, out + e.length));
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].event, ParseEvent::kMalformed);
  const Bytes len2 = {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x02, 0x00};
  seen = feed_all(p2p, cat({len2, vec("p2_write_status")}));
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.front().event, ParseEvent::kMalformed);
  EXPECT_EQ(seen.back().event, ParseEvent::kComplete);
}

TEST(DynamixelParse, ResetForgetsAPartialPacket) {
  StatusParser1<8> p;
  const Bytes& b = vec("p1_read_status");
  for (size_t i = 0; i < 4; ++i) p.feed(b[i]);
  p.reset();
  // The rest of that packet is garbage now; the next whole one parses.
  const std::vector<Seen> seen = feed_all(p, cat({Bytes(b.begin() + 4, b.end()), b}));
  ASSERT_EQ(seen.size(), 1u);
  expect_status(seen[0], status_expectations().at("p1_read_status"), "after reset");
}

// ------------------------------------------------------------ stuffing ----

TEST(DynamixelStuffing, RandomPayloadsRoundTripAndNeverShowAHeader) {
  std::mt19937 rng(20240607);
  // Mostly the bytes stuffing is about, so the patterns come often.
  const uint8_t alphabet[] = {0xFF, 0xFF, 0xFF, 0xFD, 0xFD, 0x00, 0x55, 0xFE};
  size_t stuffed_packets = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Bytes params(rng() % 48);
    for (uint8_t& b : params)
      b = (rng() % 4 == 0) ? static_cast<uint8_t>(rng()) : alphabet[rng() % sizeof alphabet];
    const uint8_t error = (rng() % 8 == 0) ? 0xFF : static_cast<uint8_t>(rng() % 8);
    uint8_t out[128];
    const Encoded e = p2::status(7, error, params.data(), params.size(), out, sizeof out);
    ASSERT_TRUE(e.ok()) << trial;
    ASSERT_LE(e.length, p2::max_packet_size(params.size() + 1)) << trial;
    stuffed_packets += e.length > p2::kOverhead + 1 + params.size();
    // LEN counts what is sent; no FF FF FD between instruction and CRC goes
    // without its stuffed FD.
    EXPECT_EQ(out[5] | out[6] << 8, static_cast<int>(e.length - p2::kHeaderSize)) << trial;
    const size_t crc_at = e.length - 2;
    for (size_t j = p2::kHeaderSize; j + 2 < crc_at;) {
      if (out[j] == 0xFF && out[j + 1] == 0xFF && out[j + 2] == 0xFD) {
        ASSERT_TRUE(j + 3 < crc_at && out[j + 3] == 0xFD) << trial << " at " << j;
        j += 4;
      } else {
        ++j;
      }
    }
    StatusParser2<48> p;
    const std::vector<Seen> seen = feed_all(p, Bytes(out, out + e.length));
    ASSERT_EQ(seen.size(), 1u) << trial;
    EXPECT_EQ(seen[0].event, ParseEvent::kComplete) << trial;
    EXPECT_EQ(seen[0].error, error) << trial;
    EXPECT_EQ(seen[0].params, params) << trial;
    // The same payload as an instruction: the same stuffing, LEN, CRC.
    uint8_t as_write[128];
    if (params.size() >= 2) {
      const uint16_t address = static_cast<uint16_t>(params[0] | params[1] << 8);
      const Encoded w = p2::write(7, address, params.data() + 2, params.size() - 2, as_write, sizeof as_write);
      if (params.size() > 2) {
        ASSERT_TRUE(w.ok()) << trial;
        uint8_t generic[128];
        const Encoded g = p2::instruction(7, 0x03, params.data(), params.size(), generic, sizeof generic);
        ASSERT_TRUE(g.ok());
        EXPECT_EQ(Bytes(as_write, as_write + w.length), Bytes(generic, generic + g.length)) << trial;
      }
    }
  }
  EXPECT_GT(stuffed_packets, 500u);  // the trials did exercise stuffing
}

TEST(DynamixelStuffing, ThePatternsAtTheEdges) {
  struct Case {
    Bytes params;
    Bytes sent;  // the parameters as they go on the line
  };
  const std::vector<Case> cases = {
      {{0xFF, 0xFF, 0xFD}, {0xFF, 0xFF, 0xFD, 0xFD}},
      {{0xFF, 0xFF, 0xFF, 0xFD}, {0xFF, 0xFF, 0xFF, 0xFD, 0xFD}},
      {{0xFF, 0xFF, 0xFD, 0xFF, 0xFF, 0xFD}, {0xFF, 0xFF, 0xFD, 0xFD, 0xFF, 0xFF, 0xFD, 0xFD}},
      {{0xFF, 0xFF, 0xFD, 0xFD}, {0xFF, 0xFF, 0xFD, 0xFD, 0xFD}},
      {{0xFF, 0xFD, 0xFF, 0xFD}, {0xFF, 0xFD, 0xFF, 0xFD}},
      {{0xFF, 0x00, 0xFF, 0xFD}, {0xFF, 0x00, 0xFF, 0xFD}},
  };
  for (const Case& c : cases) {
    uint8_t out[40];
    const Encoded e = p2::instruction(1, 0x03, c.params.data(), c.params.size(), out, sizeof out);
    ASSERT_TRUE(e.ok());
    EXPECT_EQ(Bytes(out + 8, out + e.length - 2), c.sent);
    EXPECT_EQ(out[5] | out[6] << 8, static_cast<int>(c.sent.size() + 3));
    const Encoded s = p2::status(1, 0, c.params.data(), c.params.size(), out, sizeof out);
    StatusParser2<8> p;
    const std::vector<Seen> seen = feed_all(p, Bytes(out, out + s.length));
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0].params, c.params);
  }
}

// --------------------------------------------------------------- errors ----

TEST(DynamixelErrors, Protocol1NamesEveryBit) {
  const std::vector<std::string> want = {"input voltage", "angle limit", "overheating", "range",
                                         "checksum",      "overload",    "instruction"};
  const uint8_t bits[] = {p1::kInputVoltage, p1::kAngleLimit, p1::kOverheating,     p1::kRange,
                          p1::kChecksum,     p1::kOverload,   p1::kInstructionError};
  std::set<std::string> names;
  for (int bit = 0; bit < 7; ++bit) {
    EXPECT_EQ(bits[bit], 1 << bit);
    EXPECT_EQ(p1::error_bit_name(bit), want[static_cast<size_t>(bit)]);
    const char* got[8] = {};
    ASSERT_EQ(p1::error_names(static_cast<uint8_t>(1 << bit), got, 8), 1u);
    EXPECT_EQ(std::string(got[0]), want[static_cast<size_t>(bit)]);
    names.insert(got[0]);
  }
  EXPECT_EQ(names.size(), 7u);
  EXPECT_EQ(std::string(p1::error_bit_name(7)), "bit 7");
  // The manual's example: 0x24 is overload and overheating.
  const char* got[8] = {};
  ASSERT_EQ(p1::error_names(vec("p1_error_status")[4], got, 8), 2u);
  EXPECT_EQ(std::string(got[0]), "overheating");
  EXPECT_EQ(std::string(got[1]), "overload");
  EXPECT_EQ(p1::error_names(0xFF, got, 8), 8u);
  EXPECT_EQ(p1::error_names(0xFF, got, 3), 3u);  // no more than asked
  EXPECT_EQ(p1::error_names(0x00, got, 8), 0u);
}

TEST(DynamixelErrors, Protocol2NamesEveryNumberAndTheAlert) {
  const std::vector<std::string> want = {"ok",         "result fail", "instruction error", "crc error",
                                         "data range", "data length", "data limit",        "access error"};
  for (uint8_t n = 0; n < 8; ++n) {
    EXPECT_EQ(p2::error_name(static_cast<p2::Error>(n)), want[n]);
    EXPECT_EQ(p2::error_number(n), static_cast<p2::Error>(n));
    EXPECT_EQ(p2::error_number(static_cast<uint8_t>(n | p2::kAlert)), static_cast<p2::Error>(n));
    EXPECT_FALSE(p2::alert(n));
    EXPECT_TRUE(p2::alert(static_cast<uint8_t>(n | p2::kAlert)));
  }
  EXPECT_EQ(std::string(p2::error_name(static_cast<p2::Error>(8))), "unknown error");
  EXPECT_EQ(std::string(p2::error_name(static_cast<p2::Error>(0x7F))), "unknown error");
  const char* got[4] = {};
  ASSERT_EQ(p2::error_names(0x84, got, 4), 2u);
  EXPECT_EQ(std::string(got[0]), "hardware alert");
  EXPECT_EQ(std::string(got[1]), "data range");
  ASSERT_EQ(p2::error_names(0x80, got, 4), 1u);
  EXPECT_EQ(std::string(got[0]), "hardware alert");
  ASSERT_EQ(p2::error_names(0x07, got, 4), 1u);
  EXPECT_EQ(std::string(got[0]), "access error");
  EXPECT_EQ(p2::error_names(0x00, got, 4), 0u);
  EXPECT_EQ(p2::error_names(0x84, got, 1), 1u);
}

// --------------------------------------------------------- goal ticks ----

TEST(DynamixelGoal, LinearRoundedAndHeldToTheLimits) {
  // An X series servo: 4096 ticks a turn, 2048 at 0 rad, limits 1024..3072.
  const TickMapping m{2048.0f, 4096.0f / 6.2831853f, 1024, 3072};
  int32_t t = -1;
  ASSERT_TRUE(goal_ticks(m, 0.0f, &t));
  EXPECT_EQ(t, 2048);
  ASSERT_TRUE(goal_ticks(m, 1.0f, &t));
  EXPECT_EQ(t, 2700);  // 2048 + 651.9
  ASSERT_TRUE(goal_ticks(m, -1.0f, &t));
  EXPECT_EQ(t, 1396);  // 2048 - 651.9
  ASSERT_TRUE(goal_ticks(m, 10.0f, &t));
  EXPECT_EQ(t, 3072);
  ASSERT_TRUE(goal_ticks(m, -10.0f, &t));
  EXPECT_EQ(t, 1024);
  ASSERT_TRUE(goal_ticks(m, INFINITY, &t));
  EXPECT_EQ(t, 3072);
  ASSERT_TRUE(goal_ticks(m, -INFINITY, &t));
  EXPECT_EQ(t, 1024);
  // Halves round away from zero, on both sides of it.
  const TickMapping half{0.0f, 1.0f, -100, 100};
  ASSERT_TRUE(goal_ticks(half, 2.5f, &t));
  EXPECT_EQ(t, 3);
  ASSERT_TRUE(goal_ticks(half, -2.5f, &t));
  EXPECT_EQ(t, -3);
  ASSERT_TRUE(goal_ticks(half, 2.49f, &t));
  EXPECT_EQ(t, 2);
  // A reversed servo: ticks fall as the goal rises.
  const TickMapping reversed{2048.0f, -100.0f, 0, 4095};
  ASSERT_TRUE(goal_ticks(reversed, 3.0f, &t));
  EXPECT_EQ(t, 1748);
  // The whole int32 range as limits: no overflow at the edges.
  const TickMapping wide{0.0f, 1e9f, INT32_MIN, INT32_MAX};
  ASSERT_TRUE(goal_ticks(wide, 5.0f, &t));
  EXPECT_EQ(t, INT32_MAX);
  ASSERT_TRUE(goal_ticks(wide, -5.0f, &t));
  EXPECT_EQ(t, INT32_MIN);
}

TEST(DynamixelGoal, RefusesNanAndInvertedLimitsLeavingTheTicksAlone) {
  int32_t t = 1234;
  EXPECT_FALSE(goal_ticks(TickMapping{2048.0f, 100.0f, 0, 4095}, NAN, &t));
  EXPECT_FALSE(goal_ticks(TickMapping{2048.0f, 100.0f, 4095, 0}, 1.0f, &t));
  EXPECT_FALSE(goal_ticks(TickMapping{2048.0f, 0.0f, 0, 4095}, INFINITY, &t));  // inf * 0
  EXPECT_FALSE(goal_ticks(TickMapping{2048.0f, 100.0f, 0, 4095}, 1.0f, nullptr));
  EXPECT_EQ(t, 1234);
  // A single-tick range is fine: everything goes there.
  EXPECT_TRUE(goal_ticks(TickMapping{0.0f, 1.0f, 7, 7}, -50.0f, &t));
  EXPECT_EQ(t, 7);
}

}  // namespace
}  // namespace nlsoft::fw::drivers::dynamixel
