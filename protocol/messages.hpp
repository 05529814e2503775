#pragma once
// Typed messages and their pack/unpack (PROTOCOL.md, "Messages").
//
// Each struct lists its wire fields once, in wire order, in a static
// `fields(self, visitor)` function. Packing, unpacking, the golden-vector
// text form and the signature check in the tests are all visitors over that
// one list, so a layout cannot drift between them.
//
// Only the last field of a message may vary in length (a "tail"); its
// element count follows from the payload length, so no count byte is spent
// on the wire. TELEMETRY is the exception: its optional fields follow from
// the mask and dims bytes, which come first.

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "protocol/byte_io.hpp"
#include "protocol/catalog.hpp"
#include "protocol/frame.hpp"
#include "protocol/status.hpp"

namespace nlsoft::protocol {

constexpr uint8_t kMaxParamValues = 16;
constexpr uint8_t kMaxChunkData = static_cast<uint8_t>(kMaxPayload - 5);  // 241
constexpr uint8_t kMaxNameLen = 32;
constexpr uint8_t kUnitLen = 8;
constexpr uint8_t kMaxLogText = static_cast<uint8_t>(kMaxPayload - 1);  // 245
constexpr uint8_t kMaxTelemetryDim = 15;  // n and m share one byte
constexpr uint8_t kNoField = 0xFF;        // NACK field/element "not attributable"
constexpr uint8_t kRigNameLen = 24;       // RIG_INFO rig_name, NUL-padded
// RIG_INFO's shape list: what keeps the whole reply within the reply cache
// (reply_cache.hpp: 41 fixed bytes + 78 = 119, 128 on the wire).
constexpr uint8_t kMaxShapeBytes = 78;
// IDENT_SAMPLE's vectors: m + n + w floats after 13 fixed bytes fill at
// most the 246-byte payload.
constexpr uint8_t kMaxIdentFloats = static_cast<uint8_t>((kMaxPayload - kIdentSampleFixedSize) / 4);  // 58
// A rig's sensor channels: SENSOR_HEALTH's invalid mask is a u32.
constexpr uint8_t kMaxSensorChannels = 32;

// IDENT_START.signal: numbering shared with shared/excitation.hpp.
enum class IdentSignal : uint8_t { Steps = 0, Prbs = 1, Walk = 2, Chirp = 3, Aprbs = 4 };
namespace ident_options {
constexpr uint8_t kJoint = 0x01;  // every input the same deviation (else one stream per input)
constexpr uint8_t kMixed = 0x02;  // a shared deviation plus each input's own (capability IDENT_MIXED)
}

// Numbering shared with shared/params.hpp (F32, U8, Enum) and extended.
enum class ParamType : uint8_t { F32 = 0, U8 = 1, Enum = 2, U16 = 3, U32 = 4 };

namespace param_access {
constexpr uint8_t kReadOnly = 0x01;
constexpr uint8_t kStoppedOnly = 0x02;  // may only change while no run is active
}  // namespace param_access

enum class XferKind : uint8_t { RefTable = 1, Model = 2 };

namespace xfer_options {
constexpr uint8_t kRestart = 0x01;  // discard a matching partial transfer instead of resuming
}

// Ident (protocol 1.3): an identification run, the excitation on the inputs.
enum class RunState : uint8_t { Idle = 0, Running = 1, Hold = 2, Neutral = 3, Fault = 4, Ident = 5 };
enum class HoldMode : uint8_t { Hold = 0, Neutral = 1, Resume = 2 };
enum class LogLevel : uint8_t { Debug = 0, Info = 1, Warn = 2, Error = 3 };
// Numbering shared with shared/platform_id.hpp (a static_assert in firmware/core/firmware.hpp).
enum class Platform : uint8_t { Msd = 0, Hasel = 1, Tendon = 2, Custom = 0xFF };
// Numbering shared with shared/reference.hpp's RefKind.
enum class RefId : uint8_t {
  Infinity = 0,
  Pringle = 1,
  Diagonal = 2,
  Swirl = 3,
  Step = 4,
  Table = 5,
  Hold = 6,
};

namespace capability {
constexpr uint32_t kParams = 1u << 0;
constexpr uint32_t kRefBuiltin = 1u << 1;
constexpr uint32_t kXferRefTable = 1u << 2;
constexpr uint32_t kXferModel = 1u << 3;
constexpr uint32_t kTelemetry = 1u << 4;
constexpr uint32_t kYTrue = 1u << 5;  // telemetry can carry the true plant output
constexpr uint32_t kRunHold = 1u << 6;
constexpr uint32_t kLog = 1u << 7;
constexpr uint32_t kRig = 1u << 8;  // protocol 1.2: RIG_GET answers RIG_INFO
constexpr uint32_t kIdent = 1u << 9;  // protocol 1.3: IDENT_START, IDENT_SAMPLE
constexpr uint32_t kIdentMixed = 1u << 10;  // protocol 1.3: IDENT_START honours options bit 1 MIXED
constexpr uint32_t kDevices = 1u << 11;  // protocol 1.4: DEVICE_GET answers DEVICE_STATUS; SENSOR_HEALTH
constexpr uint32_t kSettings = 1u << 12;  // protocol 1.5: SETTINGS saves the parameters to flash (PROTOCOL.md 9.11)
constexpr uint32_t kSensorStream = 1u << 13;  // protocol 1.6: SENSOR_STREAM, SENSOR_SAMPLE (a rig with sensors)
}  // namespace capability

// RIG_INFO.accept (PROTOCOL.md 7): which model shapes a model upload may have.
namespace shape_accept {
constexpr uint8_t kList = 0;  // exactly one of the shapes listed (an MCU image's kernels)
constexpr uint8_t kAny = 1;   // any shape within max_layers, max_width, max_weights (a generic kernel)
}  // namespace shape_accept

// STATUS.watchdog (PROTOCOL.md 9.7).
namespace watchdog_flags {
constexpr uint8_t kArmed = 0x01;            // the run watches the link (watchdog_ms != 0)
constexpr uint8_t kResetByWatchdog = 0x02;  // the last reset was a watchdog reset
constexpr uint8_t kTripped = 0x04;          // the link went silent during this run: safe state
}  // namespace watchdog_flags

// Minor revision of the catalogue this library implements (INFO_EX); the
// frame's version byte stays kProtocolVersion across minor revisions.
constexpr uint8_t kProtocolMinor = 8;

// ---------------------------------------------------------------- requests

struct Ping {
  static constexpr MsgType kType = MsgType::Ping;
  uint32_t nonce = 0;
  template <class S, class V> static void fields(S& s, V& v) { v.u32("nonce", s.nonce); }
};

struct InfoGet {
  static constexpr MsgType kType = MsgType::InfoGet;
  template <class S, class V> static void fields(S&, V&) {}
};

struct ParamList {
  static constexpr MsgType kType = MsgType::ParamList;
  uint16_t index = 0;
  template <class S, class V> static void fields(S& s, V& v) { v.u16("index", s.index); }
};

struct ParamGet {
  static constexpr MsgType kType = MsgType::ParamGet;
  uint16_t id = 0;
  template <class S, class V> static void fields(S& s, V& v) { v.u16("id", s.id); }
};

// Values travel as 32-bit words whose meaning comes from the parameter's
// type (PARAM_DESC): f32 bit patterns or unsigned integers. The setter does
// not repeat the type; the firmware knows it.
struct ParamSet {
  static constexpr MsgType kType = MsgType::ParamSet;
  uint16_t id = 0;
  uint8_t count = 0;
  uint32_t values[kMaxParamValues] = {};
  // Only for the text form: how the words print. Not on the wire.
  ParamType type_hint = ParamType::F32;

  void set_f32(uint8_t i, float x) { std::memcpy(&values[i], &x, 4); }
  float f32(uint8_t i) const {
    float x;
    std::memcpy(&x, &values[i], 4);
    return x;
  }
  template <class S, class V> static void fields(S& s, V& v) {
    v.u16("id", s.id);
    v.word_tail("values", s.values, s.count, kMaxParamValues, s.type_hint);
  }
};

// Same byte layout as shared/reference.hpp's RefParams on a little-endian
// machine, so the firmware may copy it as is; fields a reference does not
// use are sent as 0 and ignored.
struct RefSelect {
  static constexpr MsgType kType = MsgType::RefSelect;
  uint8_t ref_id = 0;
  uint8_t level_count = 0;  // Step: levels used (0..3)
  uint16_t hold = 0;        // Swirl, Step, Table: control steps per point (0 acts as 1)
  float a = 0.0f;           // amplitudes A, B, C
  float b = 0.0f;
  float c = 0.0f;
  float center[3] = {};  // offsets c0, c1, c2
  float omega = 0.0f;    // Infinity: rad per control step
  float lambda = 0.0f;   // Pringle, Diagonal: period in control steps
  float scale = 0.0f;    // Swirl: amplitude scale
  float levels[3] = {};  // Step: levels relative to the centre
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("ref_id", s.ref_id);
    v.u8("level_count", s.level_count);
    v.u16("hold", s.hold);
    v.f32("a", s.a);
    v.f32("b", s.b);
    v.f32("c", s.c);
    v.f32_array("center", s.center, 3, 3);
    v.f32("omega", s.omega);
    v.f32("lambda", s.lambda);
    v.f32("scale", s.scale);
    v.f32_array("levels", s.levels, 3, 3);
  }
};

struct XferBegin {
  static constexpr MsgType kType = MsgType::XferBegin;
  uint8_t kind = 0;
  uint8_t options = 0;  // xfer_options bits
  uint32_t total_size = 0;
  uint32_t crc32 = 0;
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("kind", s.kind);
    v.u8("options", s.options);
    v.u32("total_size", s.total_size);
    v.u32("crc32", s.crc32);
  }
};

struct XferChunk {
  static constexpr MsgType kType = MsgType::XferChunk;
  uint8_t kind = 0;
  uint32_t offset = 0;
  uint8_t size = 0;
  uint8_t data[kMaxChunkData] = {};
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("kind", s.kind);
    v.u32("offset", s.offset);
    v.bytes_tail("data", s.data, s.size, kMaxChunkData);
  }
};

struct XferCommit {
  static constexpr MsgType kType = MsgType::XferCommit;
  uint8_t kind = 0;
  template <class S, class V> static void fields(S& s, V& v) { v.u8("kind", s.kind); }
};

struct XferAbort {
  static constexpr MsgType kType = MsgType::XferAbort;
  uint8_t kind = 0;
  template <class S, class V> static void fields(S& s, V& v) { v.u8("kind", s.kind); }
};

struct RunStart {
  static constexpr MsgType kType = MsgType::RunStart;
  uint32_t run_id = 0;
  template <class S, class V> static void fields(S& s, V& v) { v.u32("run_id", s.run_id); }
};

struct RunStop {
  static constexpr MsgType kType = MsgType::RunStop;
  template <class S, class V> static void fields(S&, V&) {}
};

struct RunHold {
  static constexpr MsgType kType = MsgType::RunHold;
  uint8_t mode = 0;
  template <class S, class V> static void fields(S& s, V& v) { v.u8("mode", s.mode); }
};

struct TelemetryConfig {
  static constexpr MsgType kType = MsgType::TelemetryConfig;
  uint8_t mask = 0;
  uint16_t decimation = 0;  // 0 = telemetry off, k = every k-th control step
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("mask", s.mask);
    v.u16("decimation", s.decimation);
  }
};

struct StatusGet {
  static constexpr MsgType kType = MsgType::StatusGet;
  template <class S, class V> static void fields(S&, V&) {}
};

struct RigGet {
  static constexpr MsgType kType = MsgType::RigGet;
  template <class S, class V> static void fields(S&, V&) {}
};

// Protocol 1.3: starts an identification run. A request of its own: the
// run is open loop (no model, no reference), with its own telemetry.
struct IdentStart {
  static constexpr MsgType kType = MsgType::IdentStart;
  uint32_t run_id = 0;
  uint8_t signal = 0;        // IdentSignal
  uint8_t options = 0;       // ident_options bits
  uint16_t decimation = 1;   // one IDENT_SAMPLE every k control steps, k >= 1
  uint32_t seed = 0;
  float amplitude = 0.0f;    // fraction of each input's range, (0, 1]
  float band_lo = 0.0f;      // Hz
  float band_hi = 0.0f;      // Hz, <= loop rate / 2
  uint32_t duration = 0;     // control steps, >= 1; the run then ends by itself
  template <class S, class V> static void fields(S& s, V& v) {
    v.u32("run_id", s.run_id);
    v.u8("signal", s.signal);
    v.u8("options", s.options);
    v.u16("decimation", s.decimation);
    v.u32("seed", s.seed);
    v.f32("amplitude", s.amplitude);
    v.f32("band_lo", s.band_lo);
    v.f32("band_hi", s.band_hi);
    v.u32("duration", s.duration);
  }
};

// ------------------------------------------------- replies and unsolicited

struct Ack {
  static constexpr MsgType kType = MsgType::Ack;
  uint8_t request_type = 0;
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("request_type", s.request_type);
  }
};

struct Nack {
  static constexpr MsgType kType = MsgType::Nack;
  uint8_t request_type = 0;
  uint8_t status = 0;
  uint8_t field = kNoField;    // index in the request's field table
  uint8_t element = kNoField;  // index inside an array field
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("request_type", s.request_type);
    v.u8("status", s.status);
    v.u8("field", s.field);
    v.u8("element", s.element);
  }
};

struct Pong {
  static constexpr MsgType kType = MsgType::Pong;
  uint32_t nonce = 0;
  uint32_t uptime_ms = 0;
  template <class S, class V> static void fields(S& s, V& v) {
    v.u32("nonce", s.nonce);
    v.u32("uptime_ms", s.uptime_ms);
  }
};

struct Info {
  static constexpr MsgType kType = MsgType::Info;
  uint8_t protocol_version = kProtocolVersion;
  uint8_t platform = 0;
  uint8_t m = 0;
  uint8_t n = 0;
  uint8_t w = 0;
  uint8_t nd = 0;
  uint8_t dd = 0;
  uint8_t max_n = 0;
  uint8_t max_nc = 0;
  uint8_t fw_major = 0;
  uint8_t fw_minor = 0;
  uint8_t fw_patch = 0;
  uint32_t loop_rate_hz = 0;
  uint32_t model_hash = 0;
  uint32_t param_hash = 0;
  uint32_t capabilities = 0;
  char firmware[kMaxNameLen + 1] = {};
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("protocol_version", s.protocol_version);
    v.u8("platform", s.platform);
    v.u8("m", s.m);
    v.u8("n", s.n);
    v.u8("w", s.w);
    v.u8("nd", s.nd);
    v.u8("dd", s.dd);
    v.u8("max_n", s.max_n);
    v.u8("max_nc", s.max_nc);
    v.u8("fw_major", s.fw_major);
    v.u8("fw_minor", s.fw_minor);
    v.u8("fw_patch", s.fw_patch);
    v.u32("loop_rate_hz", s.loop_rate_hz);
    v.u32("model_hash", s.model_hash);
    v.u32("param_hash", s.param_hash);
    v.u32("capabilities", s.capabilities);
    v.text_tail("firmware", s.firmware, kMaxNameLen);
  }
};

// Protocol 1.1's reply to INFO_GET: INFO's fields in INFO's order, then the
// largest object each transfer kind accepts and the catalogue's minor
// revision, then the name. A new type rather than a longer INFO, because a
// layout never changes within a version (PROTOCOL.md section 11).
struct InfoEx {
  static constexpr MsgType kType = MsgType::InfoEx;
  Info info;
  uint32_t table_max = 0;  // XFER_BEGIN total_size limit, kind 1 (0: no such transfer)
  uint32_t model_max = 0;  // kind 2
  uint8_t protocol_minor = kProtocolMinor;
  template <class S, class V> static void fields(S& s, V& v) {
    auto& i = s.info;
    v.u8("protocol_version", i.protocol_version);
    v.u8("platform", i.platform);
    v.u8("m", i.m);
    v.u8("n", i.n);
    v.u8("w", i.w);
    v.u8("nd", i.nd);
    v.u8("dd", i.dd);
    v.u8("max_n", i.max_n);
    v.u8("max_nc", i.max_nc);
    v.u8("fw_major", i.fw_major);
    v.u8("fw_minor", i.fw_minor);
    v.u8("fw_patch", i.fw_patch);
    v.u32("loop_rate_hz", i.loop_rate_hz);
    v.u32("model_hash", i.model_hash);
    v.u32("param_hash", i.param_hash);
    v.u32("capabilities", i.capabilities);
    v.u32("table_max", s.table_max);
    v.u32("model_max", s.model_max);
    v.u8("protocol_minor", s.protocol_minor);
    v.text_tail("firmware", i.firmware, kMaxNameLen);
  }
};

struct ParamDesc {
  static constexpr MsgType kType = MsgType::ParamDesc;
  uint16_t index = 0;
  uint16_t count = 0;
  uint16_t id = 0;
  uint8_t type = 0;
  uint8_t size = 0;    // element count
  uint8_t access = 0;  // param_access bits
  float min = 0.0f;
  float max = 0.0f;
  char unit[kUnitLen + 1] = {};
  char name[kMaxNameLen + 1] = {};
  template <class S, class V> static void fields(S& s, V& v) {
    v.u16("index", s.index);
    v.u16("count", s.count);
    v.u16("id", s.id);
    v.u8("type", s.type);
    v.u8("size", s.size);
    v.u8("access", s.access);
    v.f32("min", s.min);
    v.f32("max", s.max);
    v.text_fixed("unit", s.unit, kUnitLen);
    v.text_tail("name", s.name, kMaxNameLen);
  }
};

struct ParamValue {
  static constexpr MsgType kType = MsgType::ParamValue;
  uint16_t id = 0;
  uint8_t type = 0;
  uint8_t count = 0;
  uint32_t values[kMaxParamValues] = {};

  void set_f32(uint8_t i, float x) { std::memcpy(&values[i], &x, 4); }
  float f32(uint8_t i) const {
    float x;
    std::memcpy(&x, &values[i], 4);
    return x;
  }
  template <class S, class V> static void fields(S& s, V& v) {
    v.u16("id", s.id);
    v.u8("type", s.type);
    v.word_tail("values", s.values, s.count, kMaxParamValues, static_cast<ParamType>(s.type));
  }
};

struct XferAck {
  static constexpr MsgType kType = MsgType::XferAck;
  uint8_t kind = 0;
  uint32_t next_offset = 0;
  uint32_t total_size = 0;
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("kind", s.kind);
    v.u32("next_offset", s.next_offset);
    v.u32("total_size", s.total_size);
  }
};

struct Status {
  static constexpr MsgType kType = MsgType::Status;
  uint32_t uptime_ms = 0;
  uint32_t run_id = 0;
  uint32_t step = 0;
  uint8_t run_state = 0;
  uint8_t watchdog = 0;
  uint8_t telemetry_mask = 0;
  uint8_t ref_id = 0;
  uint32_t frames_in = 0;
  uint32_t crc_errors = 0;
  uint32_t frame_errors = 0;  // every other decode error
  uint32_t tx_dropped = 0;
  uint32_t loop_overruns = 0;
  uint32_t compute_min = 0;  // ticks
  uint32_t compute_mean = 0;
  uint32_t compute_max = 0;
  uint32_t tick_rate_hz = 0;
  template <class S, class V> static void fields(S& s, V& v) {
    v.u32("uptime_ms", s.uptime_ms);
    v.u32("run_id", s.run_id);
    v.u32("step", s.step);
    v.u8("run_state", s.run_state);
    v.u8("watchdog", s.watchdog);
    v.u8("telemetry_mask", s.telemetry_mask);
    v.u8("ref_id", s.ref_id);
    v.u32("frames_in", s.frames_in);
    v.u32("crc_errors", s.crc_errors);
    v.u32("frame_errors", s.frame_errors);
    v.u32("tx_dropped", s.tx_dropped);
    v.u32("loop_overruns", s.loop_overruns);
    v.u32("compute_min", s.compute_min);
    v.u32("compute_mean", s.compute_mean);
    v.u32("compute_max", s.compute_max);
    v.u32("tick_rate_hz", s.tick_rate_hz);
  }
};

struct Telemetry {
  static constexpr MsgType kType = MsgType::Telemetry;
  uint16_t tseq = 0;
  uint8_t mask = 0;
  uint8_t n = 0;
  uint8_t m = 0;
  uint32_t step = 0;
  uint32_t time_us = 0;
  float y_ref[kMaxTelemetryDim] = {};
  float y_hat[kMaxTelemetryDim] = {};
  float y_true[kMaxTelemetryDim] = {};
  float u[kMaxTelemetryDim] = {};
  float cost = 0.0f;
  uint8_t iterations = 0;
  uint32_t compute_ticks = 0;
  template <class S, class V> static void fields(S& s, V& v) {
    namespace tf = telemetry_field;
    v.u16("tseq", s.tseq);
    v.u8("mask", s.mask);
    v.nibbles("n", s.n, "m", s.m);
    if (s.mask & tf::kStep) v.u32("step", s.step);
    if (s.mask & tf::kTime) v.u32("time_us", s.time_us);
    if (s.mask & tf::kYRef) v.f32_array("y_ref", s.y_ref, s.n, kMaxTelemetryDim);
    if (s.mask & tf::kYHat) v.f32_array("y_hat", s.y_hat, s.n, kMaxTelemetryDim);
    if (s.mask & tf::kYTrue) v.f32_array("y_true", s.y_true, s.n, kMaxTelemetryDim);
    if (s.mask & tf::kU) v.f32_array("u", s.u, s.m, kMaxTelemetryDim);
    if (s.mask & tf::kCost) v.f32("cost", s.cost);
    if (s.mask & tf::kSolver) {
      v.u8("iterations", s.iterations);
      v.u32("compute_ticks", s.compute_ticks);
    }
  }
};

struct Log {
  static constexpr MsgType kType = MsgType::Log;
  uint8_t level = 0;
  char text[kMaxLogText + 1] = {};
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("level", s.level);
    v.text_tail("text", s.text, kMaxLogText);
  }
};

// Protocol 1.2: the rig the image was built for and the model shapes it
// accepts. A request of its own rather than a longer INFO_EX: INFO_EX's
// layout cannot change within version 1 (PROTOCOL.md section 11), and the
// name and the shape list would not fit beside INFO_EX's 69 bytes in the
// reply cache. The shape list's bytes are in rig_shapes.hpp.
struct RigInfo {
  static constexpr MsgType kType = MsgType::RigInfo;
  uint32_t rig_hash = 0;  // CRC-32 of the rig file's canonical content; 0: not built from a rig file
  char rig_name[kRigNameLen + 1] = {};
  uint8_t m = 0, n = 0, w = 0, nd = 0, dd = 0;
  uint8_t accept = shape_accept::kList;
  uint8_t max_layers = 0;
  uint16_t max_width = 0;  // widest layer buffer: units for Dense, 3 x units for GRU
  uint32_t max_weights = 0;
  uint8_t shapes_size = 0;
  uint8_t shapes[kMaxShapeBytes] = {};
  template <class S, class V> static void fields(S& s, V& v) {
    v.u32("rig_hash", s.rig_hash);
    v.text_fixed("rig_name", s.rig_name, kRigNameLen);
    v.u8("m", s.m);
    v.u8("n", s.n);
    v.u8("w", s.w);
    v.u8("nd", s.nd);
    v.u8("dd", s.dd);
    v.u8("accept", s.accept);
    v.u8("max_layers", s.max_layers);
    v.u16("max_width", s.max_width);
    v.u32("max_weights", s.max_weights);
    v.bytes_tail("shapes", s.shapes, s.shapes_size, kMaxShapeBytes);
  }
};

// Protocol 1.3: one step of an identification run: the inputs applied, the
// outputs as measured (n = 0 when the firmware measures none) and the
// sensors. A message of its own rather than more TELEMETRY bits: TELEMETRY's
// 8-bit mask is full and its layout cannot change within version 1, and an
// identification sample is always the same three vectors, so a mask would
// only cost a byte.
struct IdentSample {
  static constexpr MsgType kType = MsgType::IdentSample;
  uint16_t tseq = 0;  // TELEMETRY's counter: one count of frames generated
  uint8_t m = 0, n = 0, w = 0;
  uint32_t step = 0;
  uint32_t time_us = 0;
  float u[kMaxIdentFloats] = {};
  float y[kMaxIdentFloats] = {};
  float l[kMaxIdentFloats] = {};
  template <class S, class V> static void fields(S& s, V& v) {
    v.u16("tseq", s.tseq);
    v.u8("m", s.m);
    v.u8("n", s.n);
    v.u8("w", s.w);
    v.u32("step", s.step);
    v.u32("time_us", s.time_us);
    v.f32_array("u", s.u, s.m, kMaxIdentFloats);
    v.f32_array("y", s.y, s.n, kMaxIdentFloats);
    v.f32_array("l", s.l, s.w, kMaxIdentFloats);
  }
};

// Protocol 1.4: a sensor chip's state, by its index in the image's device
// table (DEVICE_GET walks 0 .. count - 1, as PARAM_LIST does).
enum class DeviceState : uint8_t { Ok = 0, Absent = 1, WrongId = 2, Stopped = 3, Fault = 4 };
// As a console shows it; an unknown value (a newer firmware's) is "unknown".
constexpr const char* device_state_name(uint8_t state) {
  switch (static_cast<DeviceState>(state)) {
    case DeviceState::Ok: return "ok";
    case DeviceState::Absent: return "absent";
    case DeviceState::WrongId: return "wrong id";
    case DeviceState::Stopped: return "stopped";
    case DeviceState::Fault: return "fault";
  }
  return "unknown";
}
constexpr uint32_t kNoSample = 0xFFFFFFFFu;  // DEVICE_STATUS age_ms before a chip's first sample

struct DeviceGet {
  static constexpr MsgType kType = MsgType::DeviceGet;
  uint8_t index = 0;
  template <class S, class V> static void fields(S& s, V& v) { v.u8("index", s.index); }
};

struct DeviceStatus {
  static constexpr MsgType kType = MsgType::DeviceStatus;
  uint8_t index = 0, count = 0;
  uint8_t state = 0;    // DeviceState
  uint8_t bus = 0;      // the board's bus number (the rig's board order)
  uint8_t address = 0;  // I2C: the 7-bit address; SPI: the chip select's number
  uint32_t age_ms = 0;  // since its latest sample; kNoSample: none yet
  uint32_t faults = 0;  // failed starts and reads since boot
  char name[kMaxNameLen + 1] = {};  // the rig file's device name
  template <class S, class V> static void fields(S& s, V& v) {
    v.u8("index", s.index);
    v.u8("count", s.count);
    v.u8("state", s.state);
    v.u8("bus", s.bus);
    v.u8("address", s.address);
    v.u32("age_ms", s.age_ms);
    v.u32("faults", s.faults);
    v.text_tail("name", s.name, kMaxNameLen);
  }
};

// Protocol 1.4: the health of the sensor channels at the step of the
// TELEMETRY or IDENT_SAMPLE frame it follows. A message of its own: both
// layouts are fixed within version 1 (PROTOCOL.md 7 says why not two new
// sample types).
struct SensorHealth {
  static constexpr MsgType kType = MsgType::SensorHealth;
  uint32_t step = 0;
  uint32_t invalid = 0;  // bit i: sensor channel i holds no valid sample
  uint16_t age_ms = 0;   // the oldest valid chip sample's age, saturated at 65535
  template <class S, class V> static void fields(S& s, V& v) {
    v.u32("step", s.step);
    v.u32("invalid", s.invalid);
    v.u16("age_ms", s.age_ms);
  }
};

// Protocol 1.5: the settings that survive a power cycle (PROTOCOL.md 9.11).
enum class SettingsAction : uint8_t {
  Save = 0,      // the parameters in force become the ones every boot starts with
  Defaults = 1,  // the built-in values in force again, and at every boot from now on
  Report = 2,    // say again, in a LOG, where the settings in force came from
};

struct Settings {
  static constexpr MsgType kType = MsgType::Settings;
  uint8_t action = 0;  // SettingsAction
  template <class S, class V> static void fields(S& s, V& v) { v.u8("action", s.action); }
};

// Protocol 1.6: whether each closed-loop TELEMETRY is preceded by its
// step's SENSOR_SAMPLE (PROTOCOL.md 9.6). Off at boot.
struct SensorStream {
  static constexpr MsgType kType = MsgType::SensorStream;
  uint8_t on = 0;  // 0 off, 1 on; anything else is out_of_range
  template <class S, class V> static void fields(S& s, V& v) { v.u8("on", s.on); }
};

// Protocol 1.6: the sensors l the controller read at one closed-loop step,
// sent right before that step's TELEMETRY. A message of its own, not a
// TELEMETRY field: TELEMETRY's mask is full and its layout fixed within
// version 1 (PROTOCOL.md 7); pairing by `step` keeps its loss accounting.
struct SensorSample {
  static constexpr MsgType kType = MsgType::SensorSample;
  uint32_t step = 0;
  uint8_t w = 0;  // from the payload's length: 1..kMaxSensorChannels
  float l[kMaxSensorChannels] = {};
  template <class S, class V> static void fields(S& s, V& v) {
    v.u32("step", s.step);
    v.f32_tail("l", s.l, s.w, kMaxSensorChannels);
  }
};

// ------------------------------------------------------------- pack/unpack

namespace detail {

class PackVisitor {
 public:
  explicit PackVisitor(ByteWriter& w) : w_(w) {}
  void u8(const char*, uint8_t x) { w_.u8(x); }
  void u16(const char*, uint16_t x) { w_.u16(x); }
  void u32(const char*, uint32_t x) { w_.u32(x); }
  void f32(const char*, float x) { w_.f32(x); }
  void nibbles(const char*, uint8_t hi, const char*, uint8_t lo) {
    if (hi > 0x0F || lo > 0x0F) w_.fail();
    w_.u8(static_cast<uint8_t>((hi << 4) | lo));
  }
  void f32_array(const char*, const float* a, uint8_t count, uint8_t cap) {
    if (count > cap) return w_.fail();
    for (uint8_t i = 0; i < count; ++i) w_.f32(a[i]);
  }
  void f32_tail(const char* name, const float* a, uint8_t count, uint8_t cap) {
    f32_array(name, a, count, cap);
  }
  void word_tail(const char*, const uint32_t* a, uint8_t count, uint8_t cap, ParamType) {
    if (count > cap) return w_.fail();
    for (uint8_t i = 0; i < count; ++i) w_.u32(a[i]);
  }
  void bytes_tail(const char*, const uint8_t* a, uint8_t size, uint8_t cap) {
    if (size > cap) return w_.fail();
    w_.bytes(a, size);
  }
  void text_tail(const char*, const char* s, uint8_t cap) {
    const size_t len = strnlen(s, static_cast<size_t>(cap) + 1);
    if (len > cap) return w_.fail();
    w_.bytes(s, len);
  }
  void text_fixed(const char*, const char* s, uint8_t size) {
    const size_t len = strnlen(s, static_cast<size_t>(size) + 1);
    if (len > size) return w_.fail();
    w_.bytes(s, len);
    for (size_t i = len; i < size; ++i) w_.u8(0);
  }

 private:
  static size_t strnlen(const char* s, size_t max) {
    size_t n = 0;
    while (n < max && s[n] != '\0') ++n;
    return n;
  }
  ByteWriter& w_;
};

class UnpackVisitor {
 public:
  explicit UnpackVisitor(ByteReader& r) : r_(r) {}
  void u8(const char*, uint8_t& x) { x = r_.u8(); }
  void u16(const char*, uint16_t& x) { x = r_.u16(); }
  void u32(const char*, uint32_t& x) { x = r_.u32(); }
  void f32(const char*, float& x) { x = r_.f32(); }
  void nibbles(const char*, uint8_t& hi, const char*, uint8_t& lo) {
    const uint8_t b = r_.u8();
    hi = static_cast<uint8_t>(b >> 4);
    lo = static_cast<uint8_t>(b & 0x0F);
  }
  void f32_array(const char*, float* a, uint8_t count, uint8_t cap) {
    if (count > cap) return r_.fail();
    for (uint8_t i = 0; i < count; ++i) a[i] = r_.f32();
  }
  void f32_tail(const char*, float* a, uint8_t& count, uint8_t cap) {
    if (!tail_count(4, cap, count)) return;
    for (uint8_t i = 0; i < count; ++i) a[i] = r_.f32();
  }
  void word_tail(const char*, uint32_t* a, uint8_t& count, uint8_t cap, ParamType) {
    if (!tail_count(4, cap, count)) return;
    for (uint8_t i = 0; i < count; ++i) a[i] = r_.u32();
  }
  void bytes_tail(const char*, uint8_t* a, uint8_t& size, uint8_t cap) {
    if (!tail_count(1, cap, size)) return;
    r_.bytes(a, size);
  }
  // Text is not NUL-terminated on the wire; a NUL inside it would silently
  // shorten the string for C callers, so it is shown as '?' instead.
  void text_tail(const char*, char* s, uint8_t cap) {
    uint8_t len = 0;
    if (!tail_count(1, cap, len)) return;
    read_text(s, len);
    s[len] = '\0';
  }
  void text_fixed(const char*, char* s, uint8_t size) {
    r_.bytes(s, size);
    s[size] = '\0';  // NUL padding ends it earlier when shorter
  }

 private:
  bool tail_count(size_t elem, uint8_t cap, uint8_t& count) {
    const size_t rem = r_.remaining();
    if (rem % elem != 0 || rem / elem > cap) {
      r_.fail();
      return false;
    }
    count = static_cast<uint8_t>(rem / elem);
    return true;
  }
  void read_text(char* s, uint8_t len) {
    r_.bytes(s, len);
    for (uint8_t i = 0; i < len; ++i) {
      if (s[i] == '\0') s[i] = '?';
    }
  }
  ByteReader& r_;
};

}  // namespace detail

// Writes M's payload into out. On success stores its length and returns Ok;
// returns BadLength when a count exceeds its capacity, the payload would not
// fit, or the result breaks the type's length rule (e.g. an empty PARAM_SET).
template <class M>
StatusCode pack(const M& msg, uint8_t* out, size_t capacity, size_t& length) {
  ByteWriter w(out, capacity);
  detail::PackVisitor v(w);
  M::fields(msg, v);
  const MsgRule* rule = find_rule(static_cast<uint8_t>(M::kType));
  if (!w.ok() || rule == nullptr || !payload_length_ok(*rule, out, w.size())) {
    return StatusCode::BadLength;
  }
  length = w.size();
  return StatusCode::Ok;
}

// Reads M from a payload. Everything must be consumed: a payload that is
// longer or shorter than the fields say is BadLength, never half-read.
template <class M>
StatusCode unpack(const uint8_t* payload, size_t length, M& msg) {
  const MsgRule* rule = find_rule(static_cast<uint8_t>(M::kType));
  if (rule == nullptr || !payload_length_ok(*rule, payload, length)) {
    return StatusCode::BadLength;
  }
  ByteReader r(payload, length);
  detail::UnpackVisitor v(r);
  M::fields(msg, v);
  if (!r.ok() || r.remaining() != 0) return StatusCode::BadLength;
  return StatusCode::Ok;
}

template <class M>
StatusCode unpack(const FrameView& frame, M& msg) {
  if (frame.header.type != static_cast<uint8_t>(M::kType)) return StatusCode::Unsupported;
  return unpack(frame.payload, frame.payload_size(), msg);
}

// Calls f(M{}) with a default-constructed message of the given type; returns
// false for unknown types. For generic tooling (text form, tests), not for
// the firmware's hot path.
template <class F>
bool with_message_type(uint8_t type, F&& f) {
  switch (static_cast<MsgType>(type)) {
    case MsgType::Ping: f(Ping{}); return true;
    case MsgType::InfoGet: f(InfoGet{}); return true;
    case MsgType::ParamList: f(ParamList{}); return true;
    case MsgType::ParamGet: f(ParamGet{}); return true;
    case MsgType::ParamSet: f(ParamSet{}); return true;
    case MsgType::RefSelect: f(RefSelect{}); return true;
    case MsgType::XferBegin: f(XferBegin{}); return true;
    case MsgType::XferChunk: f(XferChunk{}); return true;
    case MsgType::XferCommit: f(XferCommit{}); return true;
    case MsgType::XferAbort: f(XferAbort{}); return true;
    case MsgType::RunStart: f(RunStart{}); return true;
    case MsgType::RunStop: f(RunStop{}); return true;
    case MsgType::RunHold: f(RunHold{}); return true;
    case MsgType::TelemetryConfig: f(TelemetryConfig{}); return true;
    case MsgType::StatusGet: f(StatusGet{}); return true;
    case MsgType::RigGet: f(RigGet{}); return true;
    case MsgType::IdentStart: f(IdentStart{}); return true;
    case MsgType::DeviceGet: f(DeviceGet{}); return true;
    case MsgType::Settings: f(Settings{}); return true;
    case MsgType::Ack: f(Ack{}); return true;
    case MsgType::Nack: f(Nack{}); return true;
    case MsgType::Pong: f(Pong{}); return true;
    case MsgType::Info: f(Info{}); return true;
    case MsgType::ParamDesc: f(ParamDesc{}); return true;
    case MsgType::ParamValue: f(ParamValue{}); return true;
    case MsgType::XferAck: f(XferAck{}); return true;
    case MsgType::Status: f(Status{}); return true;
    case MsgType::Telemetry: f(Telemetry{}); return true;
    case MsgType::Log: f(Log{}); return true;
    case MsgType::InfoEx: f(InfoEx{}); return true;
    case MsgType::RigInfo: f(RigInfo{}); return true;
    case MsgType::IdentSample: f(IdentSample{}); return true;
    case MsgType::DeviceStatus: f(DeviceStatus{}); return true;
    case MsgType::SensorHealth: f(SensorHealth{}); return true;
    case MsgType::SensorStream: f(SensorStream{}); return true;
    case MsgType::SensorSample: f(SensorSample{}); return true;
  }
  return false;
}

}  // namespace nlsoft::protocol
