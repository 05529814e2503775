#pragma once
// The message catalogue: type ids, names, payload length rules and the
// per-type CRC seed (PROTOCOL.md, "Message catalogue").
//
// The seed is derived from a layout signature string, like MAVLink's
// CRC_EXTRA: a peer built against a different layout of the same type id
// computes a different CRC and drops the frame as bad_crc instead of
// misreading its fields. Changing a layout therefore means changing its
// signature here and in PROTOCOL.md together.

#include <cstddef>
#include <cstdint>

#include "protocol/crc.hpp"
#include "protocol/frame.hpp"

namespace nlsoft::protocol {

enum class MsgType : uint8_t {
  // Requests, console -> firmware. Each gets exactly one reply.
  Ping = 0x01,
  InfoGet = 0x02,
  ParamList = 0x03,
  ParamGet = 0x04,
  ParamSet = 0x05,
  RefSelect = 0x06,
  XferBegin = 0x07,
  XferChunk = 0x08,
  XferCommit = 0x09,
  XferAbort = 0x0A,
  RunStart = 0x0B,
  RunStop = 0x0C,
  RunHold = 0x0D,
  TelemetryConfig = 0x0E,
  StatusGet = 0x0F,
  // Protocol 1.2: the rig this image was built for and the model shapes it
  // accepts (RIG_INFO), so a console refuses a model before uploading it.
  RigGet = 0x10,
  // Protocol 1.3: an identification run, open loop, the firmware's own
  // excitation signal on the inputs (IDENT_SAMPLE carries u, y and l).
  IdentStart = 0x11,
  // Protocol 1.4: one sensor chip's state (DEVICE_STATUS), by index.
  DeviceGet = 0x12,
  // Protocol 1.5: the parameters in force saved to flash, or the built-in
  // defaults back (SETTINGS action), answered ACK / NACK.
  Settings = 0x13,
  // Protocol 1.6: closed-loop runs carry the sensors l too (SENSOR_SAMPLE
  // before each TELEMETRY), what a model is trained from.
  SensorStream = 0x14,
  // Replies and unsolicited messages, firmware -> console.
  Ack = 0x40,
  Nack = 0x41,
  Pong = 0x42,
  Info = 0x43,
  ParamDesc = 0x44,
  ParamValue = 0x45,
  XferAck = 0x46,
  Status = 0x47,
  Telemetry = 0x48,
  Log = 0x49,
  // Protocol 1.1: INFO with the transfer limits. INFO (0x43) keeps its 1.0
  // layout, so a 1.1 console still reads a 1.0 firmware's INFO.
  InfoEx = 0x4A,
  RigInfo = 0x4B,  // protocol 1.2: the reply to RIG_GET
  IdentSample = 0x4C,  // protocol 1.3: one step of an identification run (unsolicited)
  DeviceStatus = 0x4D,  // protocol 1.4: the reply to DEVICE_GET
  SensorHealth = 0x4E,  // protocol 1.4: the sensor channels' health at a sample's step (unsolicited)
  SensorSample = 0x4F,  // protocol 1.6: a closed-loop step's sensors l, before its TELEMETRY (unsolicited)
};

// Telemetry field mask bits; fields appear in the payload in bit order.
namespace telemetry_field {
constexpr uint8_t kStep = 0x01;    // u32 control step index
constexpr uint8_t kTime = 0x02;    // u32 timestamp, microseconds, wraps
constexpr uint8_t kYRef = 0x04;    // f32[n]
constexpr uint8_t kYHat = 0x08;    // f32[n]
constexpr uint8_t kYTrue = 0x10;   // f32[n]
constexpr uint8_t kU = 0x20;       // f32[m]
constexpr uint8_t kCost = 0x40;    // f32
constexpr uint8_t kSolver = 0x80;  // u8 NR iterations, u32 compute ticks
constexpr uint8_t kAll = 0xFF;
}  // namespace telemetry_field

constexpr size_t kTelemetryFixedSize = 4;  // tseq u16, mask u8, dims u8

constexpr size_t telemetry_payload_size(uint8_t mask, unsigned n, unsigned m) {
  size_t size = kTelemetryFixedSize;
  if (mask & telemetry_field::kStep) size += 4;
  if (mask & telemetry_field::kTime) size += 4;
  if (mask & telemetry_field::kYRef) size += 4u * n;
  if (mask & telemetry_field::kYHat) size += 4u * n;
  if (mask & telemetry_field::kYTrue) size += 4u * n;
  if (mask & telemetry_field::kU) size += 4u * m;
  if (mask & telemetry_field::kCost) size += 4;
  if (mask & telemetry_field::kSolver) size += 5;
  return size;
}

// IDENT_SAMPLE: tseq u16, m u8, n u8, w u8, step u32, time_us u32, then
// u[m], y[n], l[w] as f32.
constexpr size_t kIdentSampleFixedSize = 13;

constexpr size_t ident_sample_payload_size(unsigned m, unsigned n, unsigned w) {
  return kIdentSampleFixedSize + 4u * (m + n + w);
}

// Length rule: min_len <= len <= max_len and (len - min_len) % step == 0.
// step 0 marks a rule that depends on the payload itself (TELEMETRY, and
// IDENT_SAMPLE, told apart by their fixed sizes).
struct MsgInfo {
  MsgType type;
  const char* name;
  const char* signature;
  uint8_t min_len;
  uint8_t max_len;
  uint8_t step;
  bool is_request;
  // Requests: the reply that carries the answer (ACK when there is no data).
  // NACK may answer any request. Replies and unsolicited messages: 0.
  MsgType reply;
};

constexpr uint8_t crc_extra_of(const char* signature) {
  const uint16_t c = crc16_str(signature);
  return static_cast<uint8_t>((c & 0xFFu) ^ (c >> 8));
}

inline constexpr MsgInfo kMessages[] = {
    {MsgType::Ping, "PING", "PING:u32 nonce", 4, 4, 1, true, MsgType::Pong},
    {MsgType::InfoGet, "INFO_GET", "INFO_GET:", 0, 0, 1, true, MsgType::InfoEx},
    {MsgType::ParamList, "PARAM_LIST", "PARAM_LIST:u16 index", 2, 2, 1, true, MsgType::ParamDesc},
    {MsgType::ParamGet, "PARAM_GET", "PARAM_GET:u16 id", 2, 2, 1, true, MsgType::ParamValue},
    {MsgType::ParamSet, "PARAM_SET", "PARAM_SET:u16 id,u32[] values", 6, 66, 4, true, MsgType::ParamValue},
    {MsgType::RefSelect, "REF_SELECT",
     "REF_SELECT:u8 ref_id,u8 level_count,u16 hold,f32 a,f32 b,f32 c,f32[3] center,f32 omega,"
     "f32 lambda,f32 scale,f32[3] levels",
     52, 52, 1, true, MsgType::Ack},
    {MsgType::XferBegin, "XFER_BEGIN", "XFER_BEGIN:u8 kind,u8 options,u32 total_size,u32 crc32",
     10, 10, 1, true, MsgType::XferAck},
    {MsgType::XferChunk, "XFER_CHUNK", "XFER_CHUNK:u8 kind,u32 offset,u8[] data", 6, 246, 1,
     true, MsgType::XferAck},
    {MsgType::XferCommit, "XFER_COMMIT", "XFER_COMMIT:u8 kind", 1, 1, 1, true, MsgType::Ack},
    {MsgType::XferAbort, "XFER_ABORT", "XFER_ABORT:u8 kind", 1, 1, 1, true, MsgType::Ack},
    {MsgType::RunStart, "RUN_START", "RUN_START:u32 run_id", 4, 4, 1, true, MsgType::Ack},
    {MsgType::RunStop, "RUN_STOP", "RUN_STOP:", 0, 0, 1, true, MsgType::Ack},
    {MsgType::RunHold, "RUN_HOLD", "RUN_HOLD:u8 mode", 1, 1, 1, true, MsgType::Ack},
    {MsgType::TelemetryConfig, "TELEMETRY_CONFIG", "TELEMETRY_CONFIG:u8 mask,u16 decimation", 3,
     3, 1, true, MsgType::Ack},
    {MsgType::StatusGet, "STATUS_GET", "STATUS_GET:", 0, 0, 1, true, MsgType::Status},
    {MsgType::RigGet, "RIG_GET", "RIG_GET:", 0, 0, 1, true, MsgType::RigInfo},
    {MsgType::IdentStart, "IDENT_START",
     "IDENT_START:u32 run_id,u8 signal,u8 options,u16 decimation,u32 seed,f32 amplitude,f32 band_lo,"
     "f32 band_hi,u32 duration",
     28, 28, 1, true, MsgType::Ack},
    {MsgType::DeviceGet, "DEVICE_GET", "DEVICE_GET:u8 index", 1, 1, 1, true, MsgType::DeviceStatus},
    {MsgType::Settings, "SETTINGS", "SETTINGS:u8 action", 1, 1, 1, true, MsgType::Ack},
    {MsgType::SensorStream, "SENSOR_STREAM", "SENSOR_STREAM:u8 on", 1, 1, 1, true, MsgType::Ack},
    {MsgType::Ack, "ACK", "ACK:u8 request_type", 1, 1, 1, false, MsgType(0)},
    {MsgType::Nack, "NACK", "NACK:u8 request_type,u8 status,u8 field,u8 element", 4, 4, 1, false, MsgType(0)},
    {MsgType::Pong, "PONG", "PONG:u32 nonce,u32 uptime_ms", 8, 8, 1, false, MsgType(0)},
    {MsgType::Info, "INFO",
     "INFO:u8 protocol_version,u8 platform,u8 m,u8 n,u8 w,u8 nd,u8 dd,u8 max_n,u8 max_nc,"
     "u8 fw_major,u8 fw_minor,u8 fw_patch,u32 loop_rate_hz,u32 model_hash,u32 param_hash,"
     "u32 capabilities,char[] firmware",
     28, 60, 1, false, MsgType(0)},
    {MsgType::ParamDesc, "PARAM_DESC",
     "PARAM_DESC:u16 index,u16 count,u16 id,u8 type,u8 size,u8 access,f32 min,f32 max,"
     "char[8] unit,char[] name",
     26, 57, 1, false, MsgType(0)},
    {MsgType::ParamValue, "PARAM_VALUE", "PARAM_VALUE:u16 id,u8 type,u32[] values", 7, 67, 4,
     false, MsgType(0)},
    {MsgType::XferAck, "XFER_ACK", "XFER_ACK:u8 kind,u32 next_offset,u32 total_size", 9, 9, 1,
     false, MsgType(0)},
    {MsgType::Status, "STATUS",
     "STATUS:u32 uptime_ms,u32 run_id,u32 step,u8 run_state,u8 watchdog,u8 telemetry_mask,"
     "u8 ref_id,u32 frames_in,u32 crc_errors,u32 frame_errors,u32 tx_dropped,"
     "u32 loop_overruns,u32 compute_min,u32 compute_mean,u32 compute_max,u32 tick_rate_hz",
     52, 52, 1, false, MsgType(0)},
    {MsgType::Telemetry, "TELEMETRY",
     "TELEMETRY:u16 tseq,u8 mask,u4 n,u4 m,?u32 step,?u32 time_us,?f32[n] y_ref,"
     "?f32[n] y_hat,?f32[n] y_true,?f32[m] u,?f32 cost,?u8 iterations,?u32 compute_ticks",
     4, static_cast<uint8_t>(kMaxPayload), 0, false, MsgType(0)},
    {MsgType::Log, "LOG", "LOG:u8 level,char[] text", 1, 246, 1, false, MsgType(0)},
    {MsgType::InfoEx, "INFO_EX",
     "INFO_EX:u8 protocol_version,u8 platform,u8 m,u8 n,u8 w,u8 nd,u8 dd,u8 max_n,u8 max_nc,"
     "u8 fw_major,u8 fw_minor,u8 fw_patch,u32 loop_rate_hz,u32 model_hash,u32 param_hash,"
     "u32 capabilities,u32 table_max,u32 model_max,u8 protocol_minor,char[] firmware",
     37, 69, 1, false, MsgType(0)},
    {MsgType::RigInfo, "RIG_INFO",
     "RIG_INFO:u32 rig_hash,char[24] rig_name,u8 m,u8 n,u8 w,u8 nd,u8 dd,u8 accept,u8 max_layers,"
     "u16 max_width,u32 max_weights,u8[] shapes",
     41, 119, 1, false, MsgType(0)},
    {MsgType::IdentSample, "IDENT_SAMPLE",
     "IDENT_SAMPLE:u16 tseq,u8 m,u8 n,u8 w,u32 step,u32 time_us,f32[m] u,f32[n] y,f32[w] l",
     static_cast<uint8_t>(kIdentSampleFixedSize), static_cast<uint8_t>(kMaxPayload), 0, false, MsgType(0)},
    {MsgType::DeviceStatus, "DEVICE_STATUS",
     "DEVICE_STATUS:u8 index,u8 count,u8 state,u8 bus,u8 address,u32 age_ms,u32 faults,char[] name", 14, 45, 1,
     false, MsgType(0)},
    {MsgType::SensorHealth, "SENSOR_HEALTH", "SENSOR_HEALTH:u32 step,u32 invalid,u16 age_ms", 10, 10, 1, false,
     MsgType(0)},
    // 1..32 sensors (SENSOR_HEALTH's u32 mask bounds a rig's channels).
    {MsgType::SensorSample, "SENSOR_SAMPLE", "SENSOR_SAMPLE:u32 step,f32[] l", 8, 132, 4, false, MsgType(0)},
};

constexpr size_t kMessageCount = sizeof(kMessages) / sizeof(kMessages[0]);

// What the decoder and pack/unpack need at run time, kept apart from the
// names and signatures so an MCU image carries ~360 bytes of catalogue
// instead of ~2 KiB of strings it never prints.
struct MsgRule {
  uint8_t crc_extra;
  uint8_t min_len;
  uint8_t max_len;
  uint8_t step;
};

namespace detail {

constexpr uint8_t kNoMessage = 0xFF;

struct TypeIndex {
  uint8_t index[256];
  MsgRule rule[kMessageCount];
};

// Dense lookup by type byte: the decoder asks once per frame, and a table
// lookup is cheaper than a search on the MCU.
constexpr TypeIndex make_type_index() {
  TypeIndex t{};
  for (unsigned i = 0; i < 256; ++i) t.index[i] = kNoMessage;
  for (size_t i = 0; i < kMessageCount; ++i) {
    const MsgInfo& m = kMessages[i];
    t.index[static_cast<uint8_t>(m.type)] = static_cast<uint8_t>(i);
    t.rule[i] = MsgRule{crc_extra_of(m.signature), m.min_len, m.max_len, m.step};
  }
  return t;
}

inline constexpr TypeIndex kTypeIndex = make_type_index();

}  // namespace detail

// nullptr for a type outside the catalogue.
constexpr const MsgRule* find_rule(uint8_t type) {
  const uint8_t i = detail::kTypeIndex.index[type];
  return i == detail::kNoMessage ? nullptr : &detail::kTypeIndex.rule[i];
}

// Only meaningful for types find_rule() knows.
constexpr uint8_t crc_extra(uint8_t type) {
  const MsgRule* r = find_rule(type);
  return r ? r->crc_extra : 0;
}

// Names and signatures: for host tools, logs and tests.
constexpr const MsgInfo* find_message(uint8_t type) {
  const uint8_t i = detail::kTypeIndex.index[type];
  return i == detail::kNoMessage ? nullptr : &kMessages[i];
}

constexpr const char* message_name(uint8_t type) {
  const MsgInfo* info = find_message(type);
  return info ? info->name : "UNKNOWN";
}

// Whether a frame of type `reply` may answer a request of type `request`
// (section 6's reply column; for ACK and NACK the client also checks that
// their request_type is the request's). A 1.0 firmware answers INFO_GET
// with INFO, a 1.1 one with INFO_EX: both answer.
constexpr bool answers(uint8_t request, uint8_t reply) {
  // A firmware NACKs any known type sent to it that is not a request.
  if (reply == uint8_t(MsgType::Nack)) return find_message(request) != nullptr;
  const MsgInfo* req = find_message(request);
  if (req == nullptr || !req->is_request) return false;
  if (request == uint8_t(MsgType::InfoGet) && reply == uint8_t(MsgType::Info)) return true;
  return reply == uint8_t(req->reply);
}

constexpr bool payload_length_ok(const MsgRule& rule, const uint8_t* payload, size_t len) {
  if (len < rule.min_len || len > rule.max_len) return false;
  if (rule.step == 0 && rule.min_len == kIdentSampleFixedSize)
    return len == ident_sample_payload_size(payload[2], payload[3], payload[4]);
  if (rule.step == 0) {
    // TELEMETRY: tseq(2) mask(1) dims(1), dims = n << 4 | m.
    const uint8_t mask = payload[2];
    const unsigned n = payload[3] >> 4;
    const unsigned m = payload[3] & 0x0Fu;
    return len == telemetry_payload_size(mask, n, m);
  }
  return (len - rule.min_len) % rule.step == 0;
}

}  // namespace nlsoft::protocol
