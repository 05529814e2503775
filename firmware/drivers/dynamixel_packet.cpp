#include "firmware/drivers/dynamixel_packet.hpp"

#include <cstring>

namespace nlsoft::fw::drivers::dynamixel {
namespace {

constexpr Encoded fail(EncodeStatus s) { return Encoded{0, s}; }

// Bytes into the caller's buffer, never past its end. stuff() is 2.0's
// byte stuffing for the instruction and parameters: after an 0xFF 0xFF 0xFD
// an extra 0xFD, so no header can be read inside the packet.
struct Writer {
  uint8_t* out;
  size_t capacity;
  size_t n = 0;
  bool overflow = false;
  uint8_t ff_run = 0;

  void put(uint8_t b) {
    if (n < capacity)
      out[n++] = b;
    else
      overflow = true;
  }
  void stuff(uint8_t b) {
    put(b);
    if (b == 0xFD && ff_run >= 2) {
      put(0xFD);
      ff_run = 0;
    } else {
      ff_run = b == 0xFF ? static_cast<uint8_t>(ff_run < 2 ? ff_run + 1 : 2) : 0;
    }
  }
};

// The table of ROBOTIS' update_crc (polynomial 0x8005, MSB first), worked
// at compile time so it sits in flash.
struct CrcTable {
  uint16_t v[256];
};
constexpr CrcTable make_crc_table() {
  CrcTable t{};
  for (unsigned i = 0; i < 256; ++i) {
    unsigned c = i << 8;
    for (int bit = 0; bit < 8; ++bit) c = (c & 0x8000u) ? (c << 1) ^ 0x8005u : c << 1;
    t.v[i] = static_cast<uint16_t>(c);
  }
  return t;
}
constexpr CrcTable kCrcTable = make_crc_table();
static_assert(kCrcTable.v[1] == 0x8005 && kCrcTable.v[2] == 0x800F && kCrcTable.v[255] == 0x0202,
              "the e-manual's update_crc table");

// 1.0's id field: 0..0xFD a servo, 0xFE everyone; 0xFF would read as header.
bool valid_id_v1(uint8_t id) { return id != 0xFF; }
// 2.0 reserves 0xFD and 0xFF (header bytes); 0xFE is the broadcast.
bool valid_id_v2(uint8_t id) { return id <= 0xFC || id == kBroadcastId; }

bool valid_targets(const SyncTarget* targets, size_t count, uint8_t max_id) {
  if (targets == nullptr || count == 0) return false;
  for (size_t i = 0; i < count; ++i)
    if (targets[i].data == nullptr || targets[i].id > max_id) return false;
  return true;
}

// 1.0: header, id, length, instruction; finish1 adds the checksum.
Writer begin1(uint8_t* out, size_t capacity, uint8_t id, size_t len, uint8_t instr) {
  Writer w{out, capacity};
  w.put(0xFF);
  w.put(0xFF);
  w.put(id);
  w.put(static_cast<uint8_t>(len));
  w.put(instr);
  return w;
}

Encoded finish1(Writer& w) {
  if (w.overflow) return fail(EncodeStatus::kOverflow);
  w.put(p1::checksum(w.out + 2, w.n - 2));
  if (w.overflow) return fail(EncodeStatus::kOverflow);
  return Encoded{w.n, EncodeStatus::kOk};
}

// 2.0: header, id, a length to fill in, the instruction (the first byte
// stuffing looks at); finish2 fills in the length and adds the CRC.
Writer begin2(uint8_t* out, size_t capacity, uint8_t id, uint8_t instr) {
  Writer w{out, capacity};
  const uint8_t header[p2::kHeaderSize] = {0xFF, 0xFF, 0xFD, 0x00, id, 0, 0};
  for (uint8_t b : header) w.put(b);
  w.stuff(instr);
  return w;
}

Encoded finish2(Writer& w) {
  if (w.overflow) return fail(EncodeStatus::kOverflow);
  const size_t len = w.n - p2::kHeaderSize + 2;
  if (len > 0xFFFF) return fail(EncodeStatus::kBadArgument);
  store_le16(w.out + 5, static_cast<uint16_t>(len));
  const uint16_t crc = p2::crc16(0, w.out, w.n);
  w.put(static_cast<uint8_t>(crc));
  w.put(static_cast<uint8_t>(crc >> 8));
  if (w.overflow) return fail(EncodeStatus::kOverflow);
  return Encoded{w.n, EncodeStatus::kOk};
}

}  // namespace

// ---------------------------------------------------------------- 1.0 ----
namespace p1 {

uint8_t checksum(const uint8_t* bytes, size_t n) {
  unsigned sum = 0;
  for (size_t i = 0; i < n; ++i) sum += bytes[i];
  return static_cast<uint8_t>(~sum);
}

Encoded instruction(uint8_t id, uint8_t instr, const uint8_t* params, size_t n, uint8_t* out, size_t capacity) {
  if (out == nullptr || (n > 0 && params == nullptr) || !valid_id_v1(id) || n > kMaxParams)
    return fail(EncodeStatus::kBadArgument);
  if (packet_size(n) > capacity) return fail(EncodeStatus::kOverflow);
  Writer w = begin1(out, capacity, id, n + 2, instr);
  for (size_t i = 0; i < n; ++i) w.put(params[i]);
  return finish1(w);
}

Encoded ping(uint8_t id, uint8_t* out, size_t capacity) {
  return instruction(id, static_cast<uint8_t>(Instruction::kPing), nullptr, 0, out, capacity);
}

Encoded read(uint8_t id, uint8_t address, uint8_t length, uint8_t* out, size_t capacity) {
  if (length == 0) return fail(EncodeStatus::kBadArgument);
  const uint8_t params[2] = {address, length};
  return instruction(id, static_cast<uint8_t>(Instruction::kRead), params, 2, out, capacity);
}

Encoded write(uint8_t id, uint8_t address, const uint8_t* data, size_t n, uint8_t* out, size_t capacity) {
  // The address is a parameter too: n + 1 of them.
  if (out == nullptr || data == nullptr || n == 0 || n + 1 > kMaxParams || !valid_id_v1(id))
    return fail(EncodeStatus::kBadArgument);
  if (packet_size(n + 1) > capacity) return fail(EncodeStatus::kOverflow);
  Writer w = begin1(out, capacity, id, n + 3, static_cast<uint8_t>(Instruction::kWrite));
  w.put(address);
  for (size_t i = 0; i < n; ++i) w.put(data[i]);
  return finish1(w);
}

Encoded sync_write(uint8_t address, uint8_t data_length, const SyncTarget* targets, size_t count, uint8_t* out,
                   size_t capacity) {
  if (out == nullptr || data_length == 0 || !valid_targets(targets, count, 0xFD)) return fail(EncodeStatus::kBadArgument);
  if (count > 255) return fail(EncodeStatus::kBadArgument);  // keeps the product below from wrapping
  const size_t len = (size_t{data_length} + 1) * count + 4;
  if (len > 0xFF) return fail(EncodeStatus::kBadArgument);
  if (len + 4 > capacity) return fail(EncodeStatus::kOverflow);
  Writer w = begin1(out, capacity, kBroadcastId, len, static_cast<uint8_t>(Instruction::kSyncWrite));
  w.put(address);
  w.put(data_length);
  for (size_t i = 0; i < count; ++i) {
    w.put(targets[i].id);
    for (size_t j = 0; j < data_length; ++j) w.put(targets[i].data[j]);
  }
  return finish1(w);
}

Encoded status(uint8_t id, uint8_t error, const uint8_t* params, size_t n, uint8_t* out, size_t capacity) {
  if (id == kBroadcastId) return fail(EncodeStatus::kBadArgument);  // nobody answers as everyone
  return instruction(id, error, params, n, out, capacity);           // the same layout, byte for byte
}

const char* error_bit_name(int bit) {
  static constexpr const char* kNames[8] = {"input voltage", "angle limit", "overheating", "range",
                                            "checksum",      "overload",    "instruction", "bit 7"};
  return bit >= 0 && bit < 8 ? kNames[bit] : "no such bit";
}

size_t error_names(uint8_t error, const char** names, size_t max) {
  size_t n = 0;
  for (int bit = 0; bit < 8 && n < max; ++bit)
    if (error & (1u << bit)) names[n++] = error_bit_name(bit);
  return n;
}

}  // namespace p1

// ---------------------------------------------------------------- 2.0 ----
namespace p2 {

uint16_t crc16(uint16_t crc, const uint8_t* bytes, size_t n) {
  for (size_t i = 0; i < n; ++i)
    crc = static_cast<uint16_t>((crc << 8) ^ kCrcTable.v[((crc >> 8) ^ bytes[i]) & 0xFF]);
  return crc;
}

Encoded instruction(uint8_t id, uint8_t instr, const uint8_t* params, size_t n, uint8_t* out, size_t capacity) {
  if (out == nullptr || (n > 0 && params == nullptr) || !valid_id_v2(id)) return fail(EncodeStatus::kBadArgument);
  Writer w = begin2(out, capacity, id, instr);
  for (size_t i = 0; i < n && !w.overflow; ++i) w.stuff(params[i]);
  return finish2(w);
}

Encoded ping(uint8_t id, uint8_t* out, size_t capacity) {
  return instruction(id, static_cast<uint8_t>(Instruction::kPing), nullptr, 0, out, capacity);
}

Encoded read(uint8_t id, uint16_t address, uint16_t length, uint8_t* out, size_t capacity) {
  if (length == 0) return fail(EncodeStatus::kBadArgument);
  uint8_t params[4];
  store_le16(params, address);
  store_le16(params + 2, length);
  return instruction(id, static_cast<uint8_t>(Instruction::kRead), params, 4, out, capacity);
}

Encoded write(uint8_t id, uint16_t address, const uint8_t* data, size_t n, uint8_t* out, size_t capacity) {
  if (out == nullptr || data == nullptr || n == 0 || !valid_id_v2(id)) return fail(EncodeStatus::kBadArgument);
  Writer w = begin2(out, capacity, id, static_cast<uint8_t>(Instruction::kWrite));
  w.stuff(static_cast<uint8_t>(address));
  w.stuff(static_cast<uint8_t>(address >> 8));
  for (size_t i = 0; i < n && !w.overflow; ++i) w.stuff(data[i]);
  return finish2(w);
}

Encoded sync_write(uint16_t address, uint16_t data_length, const SyncTarget* targets, size_t count, uint8_t* out,
                   size_t capacity) {
  if (out == nullptr || data_length == 0 || !valid_targets(targets, count, 0xFC))
    return fail(EncodeStatus::kBadArgument);
  Writer w = begin2(out, capacity, kBroadcastId, static_cast<uint8_t>(Instruction::kSyncWrite));
  w.stuff(static_cast<uint8_t>(address));
  w.stuff(static_cast<uint8_t>(address >> 8));
  w.stuff(static_cast<uint8_t>(data_length));
  w.stuff(static_cast<uint8_t>(data_length >> 8));
  for (size_t i = 0; i < count && !w.overflow; ++i) {
    w.stuff(targets[i].id);
    for (size_t j = 0; j < data_length && !w.overflow; ++j) w.stuff(targets[i].data[j]);
  }
  return finish2(w);
}

Encoded status(uint8_t id, uint8_t error, const uint8_t* params, size_t n, uint8_t* out, size_t capacity) {
  if (out == nullptr || (n > 0 && params == nullptr) || id > 0xFC) return fail(EncodeStatus::kBadArgument);
  Writer w = begin2(out, capacity, id, static_cast<uint8_t>(Instruction::kStatus));
  w.stuff(error);
  for (size_t i = 0; i < n && !w.overflow; ++i) w.stuff(params[i]);
  return finish2(w);
}

const char* error_name(Error e) {
  static constexpr const char* kNames[8] = {"ok",         "result fail", "instruction error", "crc error",
                                            "data range", "data length", "data limit",        "access error"};
  const auto i = static_cast<uint8_t>(e);
  return i < 8 ? kNames[i] : "unknown error";
}

size_t error_names(uint8_t error, const char** names, size_t max) {
  size_t n = 0;
  if (alert(error) && n < max) names[n++] = kAlertName;
  if (error_number(error) != Error::kNone && n < max) names[n++] = error_name(error_number(error));
  return n;
}

}  // namespace p2

// ------------------------------------------------------------ parsing ----

StatusParser::StatusParser(Protocol protocol, uint8_t* storage, size_t size, size_t max_params)
    : storage_(storage), size_(storage == nullptr ? 0 : size), max_params_(max_params), protocol_(protocol) {
  if (protocol_ == Protocol::k1 && max_params_ > p1::kMaxParams) max_params_ = p1::kMaxParams;
  while (max_params_ > 0 && storage_size(protocol_, max_params_) > size_) --max_params_;
  // Storage too small even for a status packet without parameters: every
  // packet is too long.
  max_total_ = storage_size(protocol_, max_params_) <= size_ ? storage_size(protocol_, max_params_) - 1 : 0;
}

void StatusParser::reset() {
  head_ = n_ = end_ = total_ = 0;
  done_ = false;
  ff_run_ = 0;
  stuffed_next_ = false;
}

ParseEvent StatusParser::feed(uint8_t byte) {
  if (size_ == 0) return ParseEvent::kNone;
  drop_done();
  if (end_ == size_ && head_ > 0) {
    std::memmove(storage_, storage_ + head_, end_ - head_);
    end_ -= head_;
    head_ = 0;
  }
  // Cannot happen: each event takes at least the byte that raised it, so
  // the unread bytes never outgrow the longest packet. Were it to, the
  // oldest byte goes, not memory past the storage.
  if (end_ == size_) rescan(ParseEvent::kNone);
  storage_[end_++] = byte;
  return run();
}

ParseEvent StatusParser::poll() {
  drop_done();
  return run();
}

ParseEvent StatusParser::idle() {
  drop_done();
  if (n_ > 0) return rescan(ParseEvent::kTruncated);
  return run();
}

ParseEvent StatusParser::run() {
  while (pending()) {
    const ParseEvent e = step();
    if (e != ParseEvent::kNone) return e;
  }
  return ParseEvent::kNone;
}

ParseEvent StatusParser::step() {
  const size_t k = n_;
  const uint8_t b = storage_[head_ + k];
  return protocol_ == Protocol::k1 ? step_v1(k, b) : step_v2(k, b);
}

ParseEvent StatusParser::rescan(ParseEvent why) {
  ++head_;
  n_ = 0;
  total_ = 0;
  done_ = false;
  ff_run_ = 0;
  stuffed_next_ = false;
  return why;
}

ParseEvent StatusParser::consume(ParseEvent why) {
  done_ = true;
  return why;
}

void StatusParser::drop_done() {
  if (!done_) return;
  head_ += n_;
  n_ = 0;
  total_ = 0;
  done_ = false;
  ff_run_ = 0;
  stuffed_next_ = false;
}

ParseEvent StatusParser::accept_id(uint8_t id) {
  id_ = id;
  return expected_ == kBroadcastId || id == expected_ ? ParseEvent::kComplete : ParseEvent::kWrongId;
}

// 1.0: 0xFF 0xFF ID LEN ERROR PARAM... CHECKSUM. No stuffing, so an 0xFF
// 0xFF inside a packet cut short can only be told from a header by the
// checksum failing, and the rescan after it.
ParseEvent StatusParser::step_v1(size_t k, uint8_t b) {
  switch (k) {
    case 0:
    case 1:
      if (b != 0xFF) return rescan(ParseEvent::kNone);
      break;
    case 2:  // 0xFF is no id: a third 0xFF, the header starts one later
      if (b == 0xFF) return rescan(ParseEvent::kNone);
      break;
    case 3:
      if (b < 2) return rescan(ParseEvent::kMalformed);
      total_ = 4 + size_t{b};
      if (total_ > max_total_) return rescan(ParseEvent::kTooLong);
      break;
    default:
      break;
  }
  ++n_;
  return k >= 4 && n_ == total_ ? finish_v1() : ParseEvent::kNone;
}

ParseEvent StatusParser::finish_v1() {
  const uint8_t* p = storage_ + head_;
  if (p1::checksum(p + 2, total_ - 3) != p[total_ - 1]) return rescan(ParseEvent::kBadChecksum);
  error_ = p[4];
  params_at_ = head_ + 5;
  param_count_ = total_ - 6;
  return consume(accept_id(p[2]));
}

// 2.0: 0xFF 0xFF 0xFD 0x00 ID LEN_L LEN_H 0x55 ERROR PARAM... CRC_L CRC_H,
// LEN counting the stuffed bytes. The stuffing is checked as the bytes come:
// an 0xFF 0xFF 0xFD not followed by the stuffed 0xFD is the next packet's
// header, the current one having been cut short.
ParseEvent StatusParser::step_v2(size_t k, uint8_t b) {
  switch (k) {
    case 0:
    case 1:
      if (b != 0xFF) return rescan(ParseEvent::kNone);
      break;
    case 2:
      if (b != 0xFD) return rescan(ParseEvent::kNone);
      break;
    case 3:
      if (b != 0x00) return rescan(ParseEvent::kNone);
      break;
    case 4:
      if (b == 0xFF || b == 0xFD) return rescan(ParseEvent::kNone);
      break;
    case 5:
      break;
    case 6: {
      const size_t len = storage_[head_ + 5] | size_t{b} << 8;
      if (len < 3) return rescan(ParseEvent::kMalformed);  // not even an instruction and a CRC
      total_ = p2::kHeaderSize + len;
      if (total_ > max_total_) return rescan(ParseEvent::kTooLong);
      break;
    }
    default:
      if (k < total_ - 2) {  // instruction and parameters: stuffed
        if (stuffed_next_) {
          if (b != 0xFD) return rescan(ParseEvent::kMalformed);
          stuffed_next_ = false;
          ff_run_ = 0;
        } else if (b == 0xFD && ff_run_ >= 2) {
          stuffed_next_ = true;
          ff_run_ = 0;
        } else {
          ff_run_ = b == 0xFF ? static_cast<uint8_t>(ff_run_ < 2 ? ff_run_ + 1 : 2) : 0;
        }
      } else if (k == total_ - 2 && stuffed_next_) {
        return rescan(ParseEvent::kMalformed);  // the stuffed 0xFD missing before the CRC
      }
      break;
  }
  ++n_;
  return k >= 7 && n_ == total_ ? finish_v2() : ParseEvent::kNone;
}

ParseEvent StatusParser::finish_v2() {
  uint8_t* p = storage_ + head_;
  const uint16_t crc = static_cast<uint16_t>(p[total_ - 2] | p[total_ - 1] << 8);
  if (p2::crc16(0, p, total_ - 2) != crc) return rescan(ParseEvent::kBadChecksum);
  id_ = p[4];
  param_count_ = 0;
  if (p[7] != static_cast<uint8_t>(Instruction::kStatus)) return consume(ParseEvent::kNotStatus);
  if (total_ < p2::kOverhead + 1) return consume(ParseEvent::kMalformed);  // no error byte
  // Unstuff the error byte and parameters in place (the stuffing was
  // checked on the way in: every skipped byte is the stuffed 0xFD).
  size_t w = 8;
  uint8_t ffs = 0;
  bool skip = false;
  for (size_t r = 8; r < total_ - 2; ++r) {
    const uint8_t b = p[r];
    if (skip) {
      skip = false;
      continue;
    }
    p[w++] = b;
    if (b == 0xFD && ffs >= 2) {
      skip = true;
      ffs = 0;
    } else {
      ffs = b == 0xFF ? static_cast<uint8_t>(ffs < 2 ? ffs + 1 : 2) : 0;
    }
  }
  error_ = p[8];
  params_at_ = head_ + 9;
  param_count_ = w - 9;
  if (param_count_ > max_params_) return consume(ParseEvent::kTooLong);
  return consume(accept_id(p[4]));
}

// ------------------------------------------------------- goal position ----

bool goal_ticks(const TickMapping& m, float goal, int32_t* ticks) {
  if (ticks == nullptr || goal != goal || m.min_ticks > m.max_ticks) return false;
  const float v = m.offset_ticks + goal * m.ticks_per_unit;
  if (v != v) return false;  // an infinite goal times a zero scale
  int32_t t;
  if (!(v > static_cast<float>(m.min_ticks)))
    t = m.min_ticks;
  else if (!(v < static_cast<float>(m.max_ticks)))
    t = m.max_ticks;
  else  // strictly inside an int32 range here: the casts cannot overflow
    t = v >= 0.0f ? static_cast<int32_t>(v + 0.5f) : -static_cast<int32_t>(-v + 0.5f);
  // A limit a float cannot hold exactly may round outwards above.
  if (t < m.min_ticks) t = m.min_ticks;
  if (t > m.max_ticks) t = m.max_ticks;
  *ticks = t;
  return true;
}

}  // namespace nlsoft::fw::drivers::dynamixel
