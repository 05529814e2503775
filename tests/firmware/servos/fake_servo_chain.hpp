#pragma once
// A chain of Dynamixel servos as a test's peer: fed the bytes a bus master
// sends, it answers as the addressed servos would (PING, READ, WRITE;
// SYNC_WRITE unanswered), each with a control table of its own, and
// misbehaves on request: an error byte in every answer, silence, an answer
// from another id, a corrupt checksum. Used in process by the driver tests
// (tests/firmware/drivers/test_dynamixel_servo.cpp) and over a pty by the
// QEMU test (fake_servo_chain_main.cpp). Instruction packets are parsed
// here, not by the firmware's codec, so the two are checked against each
// other; the checksums come from the codec's ROBOTIS functions.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "firmware/drivers/dynamixel_packet.hpp"

namespace nlsoft::test {

enum class ServoFault { kNone, kError, kSilent, kWrongId, kCorrupt };

struct FakeServo {
  uint8_t id = 1;
  uint8_t protocol = 1;
  uint16_t model = 64;
  uint8_t table[256] = {};
  ServoFault fault = ServoFault::kNone;
  uint8_t error = 0;           // the error byte of every answer under kError (2.0: with 0x80, the alert)
  uint8_t hardware_error = 0;  // 2.0: Hardware Error Status (address 70) under an alert
  uint32_t goals = 0;          // SYNC_WRITEs that reached it
  uint32_t moves = 0;          // ... whose goal differed from its first (an idle loop's are all that one, neutral)
  uint32_t goal = 0;           // its last goal position
  uint32_t first_goal = 0;

  FakeServo(uint8_t id_, uint8_t protocol_, uint16_t model_) : id(id_), protocol(protocol_), model(model_) {
    table[0] = uint8_t(model);
    table[1] = uint8_t(model >> 8);
    put(protocol == 1 ? 43 : 146, 1, 36);  // temperature, degC
  }
  void put(uint16_t address, int bytes, uint32_t v) {
    for (int i = 0; i < bytes && address + i < 256; ++i) table[address + i] = uint8_t(v >> (8 * i));
  }
  uint16_t goal_address() const { return protocol == 1 ? 30 : 116; }
  int goal_bytes() const { return protocol == 1 ? 2 : 4; }
  uint16_t position_address() const { return protocol == 1 ? 36 : 132; }
};

class FakeServoChain {
 public:
  std::vector<FakeServo> servos;
  // Called for each SYNC_WRITE goal a servo takes: (id, goal).
  std::function<void(uint8_t, uint32_t)> on_goal;
  uint32_t packets = 0, bad_packets = 0;

  FakeServo* find(uint8_t id) {
    for (FakeServo& s : servos)
      if (s.id == id) return &s;
    return nullptr;
  }

  // Bytes from the master; the answers they call for appended to `out`.
  void receive(const uint8_t* p, size_t n, std::vector<uint8_t>& out) {
    in_.insert(in_.end(), p, p + n);
    while (take_packet(out)) {
    }
  }

 private:
  std::vector<uint8_t> in_;

  // One whole packet at the front of in_, handled and removed; false when
  // the front holds no whole packet yet (garbage before a header is dropped).
  bool take_packet(std::vector<uint8_t>& out) {
    size_t h = 0;
    while (h + 1 < in_.size() && !(in_[h] == 0xFF && in_[h + 1] == 0xFF)) ++h;
    in_.erase(in_.begin(), in_.begin() + long(h));
    if (in_.size() < 4) return false;
    if (in_[2] == 0xFD && in_[3] == 0x00) return take_v2(out);
    return take_v1(out);
  }

  bool take_v1(std::vector<uint8_t>& out) {
    const size_t len = in_[3], total = 4 + len;
    if (in_.size() < total) return false;
    std::vector<uint8_t> pkt(in_.begin(), in_.begin() + long(total));
    in_.erase(in_.begin(), in_.begin() + long(total));
    ++packets;
    if (len < 2 || fw::drivers::dynamixel::p1::checksum(pkt.data() + 2, total - 3) != pkt[total - 1]) {
      ++bad_packets;
      return true;
    }
    handle(1, pkt[2], pkt[4], std::vector<uint8_t>(pkt.begin() + 5, pkt.end() - 1), out);
    return true;
  }

  bool take_v2(std::vector<uint8_t>& out) {
    if (in_.size() < 7) return false;
    const size_t len = size_t(in_[5] | in_[6] << 8), total = 7 + len;
    if (in_.size() < total) return false;
    std::vector<uint8_t> pkt(in_.begin(), in_.begin() + long(total));
    in_.erase(in_.begin(), in_.begin() + long(total));
    ++packets;
    const uint16_t crc = fw::drivers::dynamixel::p2::crc16(0, pkt.data(), total - 2);
    if (len < 3 || crc != uint16_t(pkt[total - 2] | pkt[total - 1] << 8)) {
      ++bad_packets;
      return true;
    }
    // Unstuff the instruction's parameters: FF FF FD FD -> FF FF FD.
    std::vector<uint8_t> params;
    for (size_t i = 8; i < total - 2; ++i) {
      params.push_back(pkt[i]);
      const size_t k = params.size();
      if (pkt[i] == 0xFD && k >= 3 && params[k - 2] == 0xFF && params[k - 3] == 0xFF && i + 1 < total - 2 &&
          pkt[i + 1] == 0xFD)
        ++i;
    }
    handle(2, pkt[4], pkt[7], params, out);
    return true;
  }

  // A little-endian 16-bit field of a packet's parameters.
  static uint16_t le16(const std::vector<uint8_t>& p, size_t at) {
    return static_cast<uint16_t>(p.at(at) | p.at(at + 1) << 8);
  }
  // 1.0's one-byte address or length, 2.0's two-byte one, at field `k` (0 or 1).
  static uint16_t field(uint8_t protocol, const std::vector<uint8_t>& p, size_t k) {
    return protocol == 1 ? static_cast<uint16_t>(p.at(k)) : le16(p, 2 * k);
  }

  void handle(uint8_t protocol, uint8_t id, uint8_t instr, const std::vector<uint8_t>& p, std::vector<uint8_t>& out) {
    namespace dxl = fw::drivers::dynamixel;
    if (instr == uint8_t(dxl::Instruction::kSyncWrite)) return sync_write(protocol, p);
    FakeServo* s = find(id);
    if (s == nullptr || s->protocol != protocol) return;
    if (s->protocol == 2) s->table[70] = s->fault == ServoFault::kError ? s->hardware_error : 0;
    std::vector<uint8_t> data;
    if (instr == uint8_t(dxl::Instruction::kPing)) {
      if (protocol == 2) data = {uint8_t(s->model), uint8_t(s->model >> 8), 45};
    } else if (instr == uint8_t(dxl::Instruction::kRead)) {
      const uint16_t at = field(protocol, p, 0), n = field(protocol, p, 1);
      for (size_t i = 0; i < n; ++i) data.push_back(at + i < 256 ? s->table[at + i] : uint8_t(0));
    } else if (instr == uint8_t(dxl::Instruction::kWrite)) {
      const size_t skip = protocol == 1 ? 1 : 2;
      const uint16_t at = field(protocol, p, 0);
      for (size_t i = skip; i < p.size(); ++i)
        if (at + i - skip < 256) s->table[at + i - skip] = p[i];
    } else {
      return;
    }
    answer(*s, data, out);
  }

  void sync_write(uint8_t protocol, const std::vector<uint8_t>& p) {
    const size_t head = protocol == 1 ? 2 : 4;
    if (p.size() < head) return;
    const uint16_t at = field(protocol, p, 0);
    const size_t n = field(protocol, p, 1);
    for (size_t i = head; i + 1 + n <= p.size(); i += 1 + n) {
      FakeServo* s = find(p[i]);
      if (s == nullptr || s->protocol != protocol) continue;
      uint32_t v = 0;
      for (size_t b = 0; b < n; ++b) {
        if (at + b < 256) s->table[at + b] = p[i + 1 + b];
        v |= uint32_t(p[i + 1 + b]) << (8 * b);
      }
      if (at == s->goal_address()) {
        if (s->goals++ == 0) s->first_goal = v;
        if (v != s->first_goal) ++s->moves;
        s->goal = v;
        s->put(s->position_address(), s->goal_bytes(), v);  // it gets there at once
        if (on_goal) on_goal(s->id, v);
      }
    }
  }

  void answer(const FakeServo& s, const std::vector<uint8_t>& data, std::vector<uint8_t>& out) {
    namespace dxl = fw::drivers::dynamixel;
    if (s.fault == ServoFault::kSilent) return;
    const uint8_t id = s.fault == ServoFault::kWrongId ? uint8_t(s.id + 10) : s.id;
    const uint8_t error = s.fault == ServoFault::kError ? s.error : 0;
    uint8_t buf[300];
    const dxl::Encoded e = s.protocol == 1 ? dxl::p1::status(id, error, data.data(), data.size(), buf, sizeof buf)
                                           : dxl::p2::status(id, error, data.data(), data.size(), buf, sizeof buf);
    if (!e.ok()) return;
    if (s.fault == ServoFault::kCorrupt) buf[e.length - 1] ^= 0x5A;
    out.insert(out.end(), buf, buf + e.length);
  }
};

}  // namespace nlsoft::test
