#include "firmware/drivers/dynamixel_servo.hpp"

namespace nlsoft::fw::drivers {

namespace dxl = dynamixel;
using chips::dynamixel::ControlTable;
using chips::dynamixel::table;

namespace {

// The longest instruction sent here: a 2.0 READ or WRITE of a few bytes.
constexpr size_t kPacketMax = 24;
// An answer with the present block, as received (2.0 may stuff it), and
// some room for a second servo's stray answer.
constexpr size_t kAnswerMax = 2 * dxl::p2::max_packet_size(24);

// 2.0's Hardware Error Status (address 70): the bits' reasons.
constexpr uint16_t kHardwareErrorStatus = 70;
constexpr const char* kHardwareBits[8] = {"input voltage", "bit 1",  "overheating", "motor encoder",
                                          "electrical shock", "overload", "bit 6", "bit 7"};

int32_t little_endian(const uint8_t* p, int bytes) {
  uint32_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = v << 8 | p[i];
  if (bytes == 2) return int16_t(uint16_t(v));
  return int32_t(v);
}

}  // namespace

ChipStatus DynamixelServo::transact(const uint8_t* packet, size_t n, size_t answer_params, bool absent_if_silent) {
  uint8_t storage[dxl::StatusParser::storage_size(dxl::Protocol::k2, kMaxParams)];
  dxl::StatusParser parser(protocol() == 1 ? dxl::Protocol::k1 : dxl::Protocol::k2, storage, sizeof storage,
                           kMaxParams);
  parser.expect(c_.id);
  bool other_id = false, heard = false;
  auto take = [&](dxl::ParseEvent e) {
    if (e == dxl::ParseEvent::kWrongId) other_id = true;
    if (e != dxl::ParseEvent::kComplete) return false;
    error_ = parser.error();
    n_params_ = parser.param_count() < kMaxParams ? parser.param_count() : kMaxParams;
    for (size_t i = 0; i < n_params_; ++i) params_[i] = parser.params()[i];
    return true;
  };
  // 1.0 stuffs nothing: its answer is exactly this long. 2.0's may grow by
  // its stuffing, so the bus listens until the line is quiet.
  uint8_t rx[kAnswerMax];
  const size_t expect = protocol() == 1 ? dxl::p1::packet_size(answer_params) : sizeof rx;
  // What came may be a late answer to an earlier instruction (another id,
  // or this one's to another instruction cut short): listen on, a few
  // times, for this one's, so that one late answer does not shift every
  // answer after it onto the wrong instruction.
  for (int listen = 0; listen < 3; ++listen) {
    size_t got = 0;
    (void)c_.bus->exchange(listen == 0 ? packet : nullptr, listen == 0 ? n : 0, rx,
                           expect < sizeof rx ? expect : sizeof rx, got);
    if (got == 0) break;
    heard = true;
    for (size_t i = 0; i < got; ++i) {
      if (take(parser.feed(rx[i]))) return ChipStatus::kOk;
      while (parser.pending())
        if (take(parser.poll())) return ChipStatus::kOk;
    }
  }
  // The line is quiet: an unfinished packet is given up and what it held rescanned.
  for (dxl::ParseEvent e; (e = parser.idle()) != dxl::ParseEvent::kNone;) {
    if (take(e)) return ChipStatus::kOk;
    while (parser.pending())
      if (take(parser.poll())) return ChipStatus::kOk;
  }
  if (!heard) return absent_if_silent ? ChipStatus::kAbsent : ChipStatus::kBusFault;
  // Something answered, but not this servo soundly: another id, or a corrupt packet.
  return other_id && absent_if_silent ? ChipStatus::kWrongId : ChipStatus::kBusFault;
}

ChipStatus DynamixelServo::read_item(uint16_t address, uint8_t length, bool absent_if_silent) {
  uint8_t packet[kPacketMax];
  const dxl::Encoded e = protocol() == 1 ? dxl::p1::read(c_.id, uint8_t(address), length, packet, sizeof packet)
                                         : dxl::p2::read(c_.id, address, length, packet, sizeof packet);
  if (!e.ok()) return ChipStatus::kBadConfig;
  const ChipStatus s = transact(packet, e.length, length, absent_if_silent);
  if (s != ChipStatus::kOk) return s;
  return n_params_ == length ? ChipStatus::kOk : ChipStatus::kBusFault;
}

// A sound answer's error byte: 0 is health; in 2.0 the alert bit sends us
// to the Hardware Error Status for the reason, and an error number alone
// (the instruction's fate) is a fault too.
ChipStatus DynamixelServo::judge_error() {
  hardware_error_ = 0;
  if (error_ == 0) return ChipStatus::kOk;
  if (protocol() == 2 && dxl::p2::alert(error_)) {
    const uint8_t seen = error_;
    if (read_item(kHardwareErrorStatus, 1, false) == ChipStatus::kOk) hardware_error_ = params_[0];
    error_ = seen;
  }
  return ChipStatus::kFault;
}

ChipStatus DynamixelServo::begin() {
  if (c_.bus == nullptr || c_.spec == nullptr || !chips::on_serial(*c_.spec)) return ChipStatus::kBadConfig;
  const ControlTable& t = table(protocol());
  uint8_t packet[kPacketMax];
  const dxl::Encoded ping = protocol() == 1 ? dxl::p1::ping(c_.id, packet, sizeof packet)
                                            : dxl::p2::ping(c_.id, packet, sizeof packet);
  if (!ping.ok()) return ChipStatus::kBadConfig;
  ChipStatus s = transact(packet, ping.length, protocol() == 1 ? 0 : 3, true);
  if (s != ChipStatus::kOk) return s;
  if (judge_error() != ChipStatus::kOk) return ChipStatus::kFault;
  // 2.0's PING answer carries the model number; 1.0 reads it from the table.
  uint16_t model = 0;
  if (protocol() == 2 && n_params_ >= 2) {
    model = uint16_t(params_[0] | params_[1] << 8);
  } else {
    s = read_item(t.model_number, 2, true);
    if (s != ChipStatus::kOk) return s;
    if (judge_error() != ChipStatus::kOk) return ChipStatus::kFault;
    model = uint16_t(params_[0] | params_[1] << 8);
  }
  if (model != c_.spec->model_number) return ChipStatus::kWrongId;
  return torque(true);
}

ChipStatus DynamixelServo::torque(bool on) {
  const ControlTable& t = table(protocol());
  const uint8_t value = on ? 1 : 0;
  uint8_t packet[kPacketMax];
  const dxl::Encoded e = protocol() == 1 ? dxl::p1::write(c_.id, uint8_t(t.torque_enable), &value, 1, packet, sizeof packet)
                                         : dxl::p2::write(c_.id, t.torque_enable, &value, 1, packet, sizeof packet);
  if (!e.ok()) return ChipStatus::kBadConfig;
  const ChipStatus s = transact(packet, e.length, 0, false);
  if (s != ChipStatus::kOk) return s;
  return judge_error();
}

ChipStatus DynamixelServo::read(float* out) {
  const ControlTable& t = table(protocol());
  // A lost or corrupt answer is tried once more before the servo counts as
  // stopped: one glitch on a shared line is not a servo gone.
  ChipStatus s = read_item(t.present_from, t.present_bytes, false);
  if (s == ChipStatus::kBusFault) s = read_item(t.present_from, t.present_bytes, false);
  if (s != ChipStatus::kOk) return s;
  if (judge_error() != ChipStatus::kOk) return ChipStatus::kFault;
  out[0] = float(little_endian(params_ + t.position_at, t.position_bytes));
  if (protocol() == 1) {
    // Bits 0..9 the load, bit 10 its direction (clockwise: negative).
    const uint16_t raw = uint16_t(params_[t.load_at] | params_[t.load_at + 1] << 8);
    out[1] = float(raw & 0x3FF) * ((raw & 0x400) ? -1.0f : 1.0f);
  } else {
    out[1] = float(little_endian(params_ + t.load_at, 2));
  }
  out[2] = float(params_[t.temperature_at]);
  return ChipStatus::kOk;
}

size_t DynamixelServo::fault_names(const char** names, size_t max) const {
  if (protocol() == 1) return dxl::p1::error_names(error_, names, max);
  size_t n = 0;
  for (int bit = 0; bit < 8 && n < max; ++bit)
    if (hardware_error_ & (1u << bit)) names[n++] = kHardwareBits[bit];
  const uint8_t number_only = uint8_t(error_ & ~(n > 0 ? dxl::p2::kAlert : 0u));
  return n + dxl::p2::error_names(number_only, names + n, max - n);
}

BusStatus write_goals(SerialBus& bus, const ServoGoal* goals, size_t n) {
  if (n > kMaxGoals) return BusStatus::kBusError;
  BusStatus result = BusStatus::kOk;
  for (uint8_t protocol = 1; protocol <= 2; ++protocol) {
    const ControlTable& t = table(protocol);
    uint8_t data[kMaxGoals][4];
    dxl::SyncTarget targets[kMaxGoals];
    size_t k = 0;
    for (size_t i = 0; i < n; ++i) {
      if (goals[i].protocol != protocol) continue;
      if (t.goal_bytes == 2)
        dxl::store_le16(data[k], uint16_t(goals[i].goal));
      else
        dxl::store_le32(data[k], goals[i].goal);
      targets[k] = dxl::SyncTarget{goals[i].id, data[k]};
      ++k;
    }
    if (k == 0) continue;
    uint8_t packet[dxl::p2::max_packet_size(5 + kMaxGoals * 5)];
    const dxl::Encoded e = protocol == 1
                               ? dxl::p1::sync_write(uint8_t(t.goal_position), t.goal_bytes, targets, k, packet, sizeof packet)
                               : dxl::p2::sync_write(t.goal_position, t.goal_bytes, targets, k, packet, sizeof packet);
    if (!e.ok()) return BusStatus::kBusError;
    if (bus.send(packet, e.length) != BusStatus::kOk) result = BusStatus::kBusError;
  }
  return result;
}

}  // namespace nlsoft::fw::drivers
