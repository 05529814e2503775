#pragma once
// ROBOTIS Dynamixel packets, both protocols, as bytes: instruction packets
// encoded into a caller's buffer, status packets parsed one received byte at
// a time. No bus here: the firmware puts the bytes on a single-wire
// half-duplex USART and feeds back what it reads (its own echo included,
// which the parser skips).
//
// From the ROBOTIS e-manual:
//   Protocol 1.0 (RX, AX, MX before firmware 39), https://emanual.robotis.com/docs/en/dxl/protocol1/
//     "Instruction Packet", "Status Packet" (the error bits), "Instruction
//     Details" (Ping, Read, Write, Sync Write).
//   Protocol 2.0 (X series, MX from firmware 39), https://emanual.robotis.com/docs/en/dxl/protocol2/
//     "Instruction Packet", "Status Packet" (alert bit, error numbers),
//     "Packet Process" (byte stuffing), "Instruction Details" (Ping, Read,
//     Write, Sync Write); the CRC from https://emanual.robotis.com/docs/en/dxl/crc/
//     (update_crc: CRC-16, polynomial 0x8005, initial value 0, not reflected).
// tests/firmware/drivers/dynamixel_vectors.txt holds the manual's example
// packets, which the tests encode and parse byte for byte.
//
// Nothing is allocated and nothing throws: an encoder writes at most
// `capacity` bytes and says why it wrote none; a parser's storage is fixed
// when it is declared.
#include <cstddef>
#include <cstdint>

namespace nlsoft::fw::drivers::dynamixel {

// Every servo executes a packet sent to it, and none answers (but to PING).
constexpr uint8_t kBroadcastId = 0xFE;

enum class Instruction : uint8_t {
  kPing = 0x01,
  kRead = 0x02,
  kWrite = 0x03,
  kRegWrite = 0x04,
  kAction = 0x05,
  kFactoryReset = 0x06,
  kReboot = 0x08,   // 2.0
  kStatus = 0x55,   // 2.0: the instruction byte of every status packet
  kSyncRead = 0x82, // 2.0
  kSyncWrite = 0x83,
};

enum class EncodeStatus : uint8_t {
  kOk = 0,
  kOverflow = 1,     // the packet does not fit the caller's buffer
  kBadArgument = 2,  // no packet of the protocol says this (an id it reserves, a length its fields cannot hold,
                     // zero bytes to read or write, a null pointer)
};

// An encoder's answer: the packet's length in out[], or why there is none
// (length 0; out[] then holds nothing usable).
struct Encoded {
  size_t length = 0;
  EncodeStatus status = EncodeStatus::kBadArgument;
  bool ok() const { return status == EncodeStatus::kOk; }
};

// One servo's share of a SYNC_WRITE: its id and the data_length bytes it is
// to be written (the same address and length for every servo).
struct SyncTarget {
  uint8_t id;
  const uint8_t* data;
};

// Little-endian stores, for the data of a WRITE or SYNC_WRITE (both
// protocols put multi-byte control-table items low byte first).
inline void store_le16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}
inline void store_le32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}

// ---------------------------------------------------------------- 1.0 ----
// 0xFF 0xFF ID LEN INSTR PARAM... CHECKSUM; LEN = params + 2;
// CHECKSUM = ~(ID + LEN + INSTR + params) & 0xFF.
namespace p1 {

constexpr size_t kOverhead = 6;        // header, id, length, instruction, checksum
constexpr size_t kMaxParams = 253;     // LEN is one byte
constexpr size_t packet_size(size_t params) { return kOverhead + params; }

// ~(sum of bytes) & 0xFF: the checksum over a packet's id .. last parameter.
uint8_t checksum(const uint8_t* bytes, size_t n);

// Any instruction (REG_WRITE, ACTION, FACTORY_RESET, ...): id 0..0xFD or
// kBroadcastId; at most kMaxParams parameters.
Encoded instruction(uint8_t id, uint8_t instr, const uint8_t* params, size_t n, uint8_t* out, size_t capacity);
Encoded ping(uint8_t id, uint8_t* out, size_t capacity);
// `length` (1..255) bytes from control-table `address`.
Encoded read(uint8_t id, uint8_t address, uint8_t length, uint8_t* out, size_t capacity);
// n (1..252) bytes to control-table `address` on.
Encoded write(uint8_t id, uint8_t address, const uint8_t* data, size_t n, uint8_t* out, size_t capacity);
// The same `data_length` bytes from `address` on, to each of `count` servos
// (ids 0..0xFD), broadcast: LEN = (data_length + 1) * count + 4 must fit a byte.
Encoded sync_write(uint8_t address, uint8_t data_length, const SyncTarget* targets, size_t count, uint8_t* out,
                   size_t capacity);
// A servo's answer (a simulated servo's, a test's): the error byte where
// an instruction packet has its instruction.
Encoded status(uint8_t id, uint8_t error, const uint8_t* params, size_t n, uint8_t* out, size_t capacity);

// The status packet's error byte: one bit per reason.
enum Error : uint8_t {
  kInputVoltage = 0x01,
  kAngleLimit = 0x02,
  kOverheating = 0x04,
  kRange = 0x08,
  kChecksum = 0x10,
  kOverload = 0x20,
  kInstructionError = 0x40,
};
// A short name for error bit `bit` (0..7): "overload", ...; bit 7 is no
// reason the manual gives ("bit 7").
const char* error_bit_name(int bit);
// The names of the bits set in `error`, lowest bit first, at most `max` of
// them; how many were written.
size_t error_names(uint8_t error, const char** names, size_t max);

}  // namespace p1

// ---------------------------------------------------------------- 2.0 ----
// 0xFF 0xFF 0xFD 0x00 ID LEN_L LEN_H INSTR PARAM... CRC_L CRC_H;
// LEN = instruction + parameters (as sent, stuffed) + CRC. In the
// instruction and parameters every 0xFF 0xFF 0xFD is sent as
// 0xFF 0xFF 0xFD 0xFD, so a header never appears inside a packet.
namespace p2 {

constexpr size_t kHeaderSize = 7;  // 0xFF 0xFF 0xFD 0x00 ID LEN_L LEN_H
constexpr size_t kOverhead = 10;   // header, instruction, CRC
// The longest a packet of `params` parameters can be once stuffed: one
// extra byte for every three.
constexpr size_t max_packet_size(size_t params) { return kOverhead + params + params / 3; }

// ROBOTIS' update_crc: CRC-16/0x8005 of n bytes, continuing from crc (0 to
// start). A packet's CRC covers header to last parameter, as sent.
uint16_t crc16(uint16_t crc, const uint8_t* bytes, size_t n);

// Any instruction, id 0..0xFC or kBroadcastId; parameters as the manual
// lists them (unstuffed: the encoder stuffs).
Encoded instruction(uint8_t id, uint8_t instr, const uint8_t* params, size_t n, uint8_t* out, size_t capacity);
Encoded ping(uint8_t id, uint8_t* out, size_t capacity);
Encoded read(uint8_t id, uint16_t address, uint16_t length, uint8_t* out, size_t capacity);
Encoded write(uint8_t id, uint16_t address, const uint8_t* data, size_t n, uint8_t* out, size_t capacity);
// ids 0..0xFC, data_length >= 1, count >= 1.
Encoded sync_write(uint16_t address, uint16_t data_length, const SyncTarget* targets, size_t count, uint8_t* out,
                   size_t capacity);
// A servo's answer: instruction 0x55, then the error byte and parameters,
// stuffed like an instruction's parameters. id 0..0xFC.
Encoded status(uint8_t id, uint8_t error, const uint8_t* params, size_t n, uint8_t* out, size_t capacity);

// The status packet's error byte: bit 7 the alert (the servo's Hardware
// Error Status is set: read it for why), bits 0..6 a number, the
// instruction's fate.
constexpr uint8_t kAlert = 0x80;
enum class Error : uint8_t {
  kNone = 0,
  kResultFail = 1,
  kInstructionError = 2,
  kCrcError = 3,
  kDataRange = 4,
  kDataLength = 5,
  kDataLimit = 6,
  kAccessError = 7,
};
inline bool alert(uint8_t error) { return (error & kAlert) != 0; }
inline Error error_number(uint8_t error) { return static_cast<Error>(error & 0x7F); }
// "data range", ...; "ok" for kNone, "unknown error" for a number the
// manual does not list.
const char* error_name(Error e);
constexpr const char* kAlertName = "hardware alert";
// The alert (first) and the error number's name, for those set; how many
// were written (at most `max`).
size_t error_names(uint8_t error, const char** names, size_t max);

}  // namespace p2

// ------------------------------------------------------------ parsing ----

enum class Protocol : uint8_t { k1 = 1, k2 = 2 };

enum class ParseEvent : uint8_t {
  kNone = 0,         // no packet ended with this byte
  kComplete = 1,     // a status packet from the expected id: id(), error(), params()
  kWrongId = 2,      // a sound status packet from another id (id() says which); skipped
  kNotStatus = 3,    // 2.0: a sound packet that is no status packet (the line's echo of an instruction); skipped
  kBadChecksum = 4,  // the 1.0 checksum or the 2.0 CRC does not match
  kTooLong = 5,      // longer than the parser holds: its length field, or (2.0) its parameters once unstuffed
  kMalformed = 6,    // a length field too short to be a status packet; 2.0: a header inside the body (the packet
                     // was cut short) or stuffing missing
  kTruncated = 7,    // idle(): the line went quiet with a packet unfinished
};

// A status packet parser, fed the received bytes one at a time. On anything
// but a sound packet it resynchronises: the bytes after the failed packet's
// first byte are scanned again for a header, so a packet cut short does not
// take the good one after it along. Those rescanned bytes may hold more than
// one packet: after an event, while pending(), poll() goes on with them
// before the next feed(). A length field that promises more bytes than ever
// come (cut short, corrupted) holds what follows until the bus master's
// timeout says the line is quiet: idle() then gives that packet up and the
// rescan finds what it held.
//
// Declare a StatusParser1<N> or StatusParser2<N> (N the most parameters
// expected, 2.0's counted unstuffed), or give this one storage of
// storage_size(protocol, N) bytes. Neither copies nor moves: it points into
// its storage.
class StatusParser {
 public:
  static constexpr size_t storage_size(Protocol p, size_t max_params) {
    // One byte more than the longest packet: the byte fed while the last
    // event's rescan is still pending. 2.0 stuffs the error byte with the
    // parameters, hence max_params + 1 stuffable bytes.
    return (p == Protocol::k1 ? p1::packet_size(max_params) : p2::max_packet_size(max_params + 1)) + 1;
  }

  // storage_size bytes of storage for max_params parameters (fewer when the
  // storage is smaller).
  StatusParser(Protocol protocol, uint8_t* storage, size_t size, size_t max_params);
  StatusParser(const StatusParser&) = delete;
  StatusParser& operator=(const StatusParser&) = delete;

  // The id whose status packets count (kComplete); others are kWrongId.
  // kBroadcastId takes any (the answers to a broadcast PING).
  void expect(uint8_t id) { expected_ = id; }
  // Forget every byte fed, unfinished packet and all.
  void reset();

  ParseEvent feed(uint8_t byte);
  ParseEvent poll();
  bool pending() const { return head_ + n_ < end_; }
  // The line is quiet: kTruncated if a packet was unfinished (its bytes are
  // then rescanned: poll() while pending(), then idle() again until it says
  // kNone), else kNone.
  ParseEvent idle();

  // The last packet kComplete or kWrongId reported; valid until the next
  // feed(), poll() or reset().
  uint8_t id() const { return id_; }
  uint8_t error() const { return error_; }
  const uint8_t* params() const { return storage_ + params_at_; }
  size_t param_count() const { return param_count_; }
  size_t max_params() const { return max_params_; }

 private:
  ParseEvent run();
  ParseEvent step();
  ParseEvent step_v1(size_t k, uint8_t b);
  ParseEvent step_v2(size_t k, uint8_t b);
  ParseEvent finish_v1();
  ParseEvent finish_v2();
  // Give up the candidate: everything after its first byte is scanned again.
  ParseEvent rescan(ParseEvent why);
  // Report a sound packet; drop_done() skips it on the next call.
  ParseEvent consume(ParseEvent why);
  void drop_done();
  ParseEvent accept_id(uint8_t id);

  uint8_t* storage_;
  size_t size_;
  size_t max_params_;
  size_t max_total_;  // the longest packet taken, as received
  Protocol protocol_;
  uint8_t expected_ = kBroadcastId;
  // storage_[head_, head_ + n_) is the packet taking shape, [head_ + n_,
  // end_) the bytes not looked at yet.
  size_t head_ = 0;
  size_t n_ = 0;
  size_t end_ = 0;
  size_t total_ = 0;  // the candidate's length once its length field is in
  bool done_ = false; // the candidate was reported whole: drop it on the next call
  // 2.0 stuffing: 0xFF bytes in a row before this one, and whether the
  // last three were 0xFF 0xFF 0xFD (so this one must be the stuffed 0xFD).
  uint8_t ff_run_ = 0;
  bool stuffed_next_ = false;
  uint8_t id_ = 0;
  uint8_t error_ = 0;
  size_t params_at_ = 0;
  size_t param_count_ = 0;
};

template <size_t MaxParams>
class StatusParser1 final : public StatusParser {
 public:
  StatusParser1() : StatusParser(Protocol::k1, buffer_, sizeof buffer_, MaxParams) {}

 private:
  uint8_t buffer_[storage_size(Protocol::k1, MaxParams)];
};

template <size_t MaxParams>
class StatusParser2 final : public StatusParser {
 public:
  StatusParser2() : StatusParser(Protocol::k2, buffer_, sizeof buffer_, MaxParams) {}

 private:
  uint8_t buffer_[storage_size(Protocol::k2, MaxParams)];
};

// ------------------------------------------------------- goal position ----

// A controller input's unit to goal-position ticks: offset + goal *
// ticks_per_unit, rounded, held to [min_ticks, max_ticks] (the servo's
// angle limits, or a mechanism's).
struct TickMapping {
  float offset_ticks;
  float ticks_per_unit;
  int32_t min_ticks;
  int32_t max_ticks;
};

// false, *ticks untouched, for a NaN goal or min_ticks > max_ticks: the
// caller keeps the last goal rather than send one nobody asked for.
bool goal_ticks(const TickMapping& m, float goal, int32_t* ticks);

}  // namespace nlsoft::fw::drivers::dynamixel
