// Regenerates protocol/vectors/golden.txt and the golden model file:
//   nlsoft-gen-vectors > protocol/vectors/golden.txt
//   nlsoft-gen-vectors --model > protocol/vectors/model_msd.txt
// The expectations written next to each wire image are what the decoder
// reports for it; review the diff of golden.txt by hand whenever it changes,
// because once checked in it is the contract both peers are tested against.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "protocol/cobs.hpp"
#include "protocol/encoder.hpp"
#include "protocol/messages.hpp"
#include "protocol/host/golden_reader.hpp"

namespace {

using namespace nlsoft::protocol;
using Bytes = std::vector<uint8_t>;

struct Entry {
  std::string name;
  std::string note;
  Bytes wire;
};

std::vector<Entry> g_entries;

void add(const std::string& name, const std::string& note, const Bytes& wire) {
  g_entries.push_back({name, note, wire});
}

template <class M>
Bytes frame(const M& msg, uint8_t seq, uint8_t flags = 0) {
  uint8_t buf[kWireBufferSize];
  const size_t n = encode(msg, seq, flags, buf, sizeof buf);
  if (n == 0) {
    std::fprintf(stderr, "encode failed for %s\n", message_name(static_cast<uint8_t>(M::kType)));
    std::exit(1);
  }
  return Bytes(buf, buf + n);
}

// A raw (pre-COBS) frame, for building damaged frames byte by byte.
template <class M>
Bytes raw_frame(const M& msg, uint8_t seq, uint8_t flags = 0) {
  const Bytes wire = frame(msg, seq, flags);
  Bytes raw(kMaxRawFrame + 8);
  const CobsDecodeResult r = cobs_decode(wire.data(), wire.size() - 1, raw.data(), raw.size());
  raw.resize(r.size);
  return raw;
}

Bytes cobs_wire(const Bytes& raw) {
  Bytes out(cobs_max_encoded_size(raw.size()) + 1);
  const size_t n = cobs_encode(raw.data(), raw.size(), out.data(), out.size());
  out.resize(n);
  out.push_back(0);
  return out;
}

// Re-seals a raw frame's CRC (with the seed of `seed_type`) after editing it.
void reseal(Bytes& raw, uint8_t seed_type) {
  const size_t body = raw.size() - 2;
  uint16_t crc = crc16(raw.data(), body);
  crc = crc16_update(crc, crc_extra(seed_type));
  raw[body] = static_cast<uint8_t>(crc & 0xFF);
  raw[body + 1] = static_cast<uint8_t>(crc >> 8);
}

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

void set_text(char* dst, const char* src) { std::strcpy(dst, src); }

// The messages that other vectors are made of as well (the streams, the
// damaged frames), each built once.
Ping handshake_ping() {
  Ping ping;
  ping.nonce = 0x12345678u;
  return ping;
}

Pong handshake_pong() {
  Pong pong;
  pong.nonce = 0x12345678u;
  pong.uptime_ms = 987654;
  return pong;
}

Info hasel_info() {
  Info info;
  info.platform = static_cast<uint8_t>(Platform::Hasel);
  info.m = 6;
  info.n = 3;
  info.w = 18;
  info.nd = 2;
  info.dd = 2;
  info.max_n = 8;
  info.max_nc = 4;
  info.fw_major = 0;
  info.fw_minor = 1;
  info.fw_patch = 0;
  info.loop_rate_hz = 130;
  info.model_hash = 0xDEADBEEFu;
  info.param_hash = 0x0BADF00Du;
  info.capabilities = capability::kParams | capability::kRefBuiltin |
                      capability::kXferRefTable | capability::kXferModel |
                      capability::kTelemetry | capability::kYTrue | capability::kRunHold |
                      capability::kLog;
  set_text(info.firmware, "nlsoft-fw posix");
  return info;
}

Telemetry msd_compact_telemetry() {
  Telemetry tmin;
  tmin.tseq = 1;
  tmin.mask = telemetry_field::kStep | telemetry_field::kYHat | telemetry_field::kU;
  tmin.n = 1;
  tmin.m = 1;
  tmin.step = 10;
  tmin.y_hat[0] = 0.25f;
  tmin.u[0] = -3.5f;
  return tmin;
}

// ------------------------------------------------------------ requests
void handshake_and_param_requests() {
  add("ping", "Handshake probe; the reply is PONG with the same nonce.", frame(handshake_ping(), 1));

  add("info_get", "", frame(InfoGet{}, 2));

  ParamList plist;
  plist.index = 0;
  add("param_list_first", "Ask for the description of parameter #0.", frame(plist, 3));

  ParamGet pget;
  pget.id = 3;
  add("param_get", "", frame(pget, 4));

  ParamSet q;
  q.id = 3;
  q.count = 3;
  q.set_f32(0, 1e6f);
  q.set_f32(1, 2e6f);
  q.set_f32(2, 1e6f);
  add("param_set_vector", "Q diagonal of the hasel config in one message.", frame(q, 5));

  ParamSet horizon;
  horizon.id = 10;
  horizon.count = 1;
  horizon.values[0] = 3;
  add("param_set_integer",
      "An integer parameter (N = 3): integer words print as bit patterns in the text form.",
      frame(horizon, 6));

  ParamSet nan_set;
  nan_set.id = 3;
  nan_set.count = 3;
  nan_set.set_f32(0, 1.0f);
  nan_set.values[1] = 0x7FC00000u;
  nan_set.set_f32(2, 1.0f);
  add("param_set_non_finite",
      "Well-formed frame carrying a NaN; the firmware must NACK it with not_finite, field 1, "
      "element 1.",
      frame(nan_set, 7));
}

void ref_and_transfer_requests() {
  RefSelect inf;
  inf.ref_id = static_cast<uint8_t>(RefId::Infinity);
  inf.a = 2.0f;
  inf.b = 3.0f;
  inf.c = 1.5f;
  inf.center[1] = 0.5f;
  inf.center[2] = -0.25f;
  inf.omega = 0.05f;
  add("ref_select_infinity", "Infinity reference; unused fields are 0.", frame(inf, 8));

  RefSelect steps;
  steps.ref_id = static_cast<uint8_t>(RefId::Step);
  steps.level_count = 3;
  steps.hold = 2000;
  steps.levels[0] = 0.5f;
  steps.levels[1] = 1.0f;
  steps.levels[2] = 2.0f;
  add("ref_select_step", "The msd step task: 0.5, 1, 2 m, each held 2000 steps.", frame(steps, 9));

  XferBegin begin;
  begin.kind = static_cast<uint8_t>(XferKind::RefTable);
  begin.total_size = 1234;
  begin.crc32 = 0xCBF43926u;
  add("xfer_begin", "", frame(begin, 10));

  XferChunk chunk;
  chunk.kind = static_cast<uint8_t>(XferKind::RefTable);
  chunk.offset = 240;
  chunk.size = 16;
  for (uint8_t i = 0; i < chunk.size; ++i) chunk.data[i] = static_cast<uint8_t>(i * 17);
  add("xfer_chunk", "Data with zero bytes in it, which COBS must remove.", frame(chunk, 11));

  XferChunk big;
  big.kind = static_cast<uint8_t>(XferKind::Model);
  big.offset = 0x00010203u;
  big.size = kMaxChunkData;
  for (unsigned i = 0; i < big.size; ++i) big.data[i] = static_cast<uint8_t>(1 + i % 255);
  add("xfer_chunk_largest",
      "Largest frame: 241 data bytes, 253 raw bytes, 255 bytes on the wire.", frame(big, 12));

  XferCommit commit;
  commit.kind = static_cast<uint8_t>(XferKind::RefTable);
  add("xfer_commit", "", frame(commit, 13));

  XferAbort abort_msg;
  abort_msg.kind = static_cast<uint8_t>(XferKind::Model);
  add("xfer_abort", "", frame(abort_msg, 14));
}

void run_requests() {
  RunStart start;
  start.run_id = 42;
  add("run_start", "", frame(start, 15));
  add("run_stop", "", frame(RunStop{}, 16));

  RunHold hold;
  hold.mode = static_cast<uint8_t>(HoldMode::Neutral);
  add("run_hold_neutral", "", frame(hold, 17));

  TelemetryConfig tcfg;
  tcfg.mask = telemetry_field::kAll;
  tcfg.decimation = 1;
  add("telemetry_config_all", "", frame(tcfg, 18));

  add("status_get", "Sequence number 255, the last before wrapping to 0.",
      frame(StatusGet{}, 255));
  add("rig_get", "Protocol 1.2: asks for RIG_INFO; sent when INFO_EX has the RIG capability.", frame(RigGet{}, 30));
}

void ident_requests() {
  IdentStart ident;
  ident.run_id = 43;
  ident.signal = static_cast<uint8_t>(IdentSignal::Prbs);
  ident.options = 0;
  ident.decimation = 1;
  ident.seed = 7;
  ident.amplitude = 0.8f;
  ident.band_lo = 0.05f;
  ident.band_hi = 5.0f;
  ident.duration = 78000;
  add("ident_start_prbs", "Protocol 1.3: a 10-minute PRBS identification run at 130 Hz, one input stream each, every step sent.",
      frame(ident, 31));
  IdentStart ident_joint = ident;
  ident_joint.run_id = 44;
  ident_joint.signal = static_cast<uint8_t>(IdentSignal::Chirp);
  ident_joint.options = ident_options::kJoint;
  ident_joint.decimation = 3;
  ident_joint.band_lo = 0.1f;
  ident_joint.band_hi = 20.0f;
  ident_joint.duration = 60000;
  add("ident_start_chirp_joint",
      "Protocol 1.3: a joint chirp of 60 s at 1 kHz, one sample every 3 steps (333 samples/s: over full-speed USB; "
      "at 115200 baud msd needs 4, section 7).",
      frame(ident_joint, 32));
  IdentStart ident_mixed = ident;
  ident_mixed.run_id = 45;
  ident_mixed.signal = static_cast<uint8_t>(IdentSignal::Aprbs);
  ident_mixed.options = ident_options::kMixed;
  add("ident_start_aprbs_mixed",
      "Protocol 1.3: a 10-minute APRBS run at 130 Hz, mixed: a shared level under each input's own (sent only to a "
      "firmware with the IDENT_MIXED capability).",
      frame(ident_mixed, 33));
}

// ------------------------------------------------- replies, unsolicited
void acks_and_nacks() {
  Ack ack;
  ack.request_type = static_cast<uint8_t>(MsgType::RunStart);
  add("ack_run_start", "Reply to run_start: same seq, REPLY flag.",
      frame(ack, 15, frame_flags::kReply));

  Nack nack;
  nack.request_type = static_cast<uint8_t>(MsgType::ParamSet);
  nack.status = static_cast<uint8_t>(StatusCode::NotFinite);
  nack.field = 1;
  nack.element = 1;
  add("nack_param_set_non_finite", "Reply to param_set_non_finite.",
      frame(nack, 7, frame_flags::kReply));

  Nack nack_plain;
  nack_plain.request_type = static_cast<uint8_t>(MsgType::XferCommit);
  nack_plain.status = static_cast<uint8_t>(StatusCode::BadChecksum);
  add("nack_xfer_commit_crc", "No single field to blame: field and element are 255.",
      frame(nack_plain, 13, frame_flags::kReply));

  Nack nack_ref;
  nack_ref.request_type = static_cast<uint8_t>(MsgType::RefSelect);
  nack_ref.status = static_cast<uint8_t>(StatusCode::NotFinite);
  nack_ref.field = 6;
  nack_ref.element = 2;
  add("nack_ref_select_center", "REF_SELECT refused: center[2] (field 6, element 2) is not finite.",
      frame(nack_ref, 14, frame_flags::kReply));

  Nack nack_big;
  nack_big.request_type = static_cast<uint8_t>(MsgType::XferBegin);
  nack_big.status = static_cast<uint8_t>(StatusCode::TooLarge);
  nack_big.field = 2;
  add("nack_xfer_begin_too_large", "total_size (field 2) above INFO_EX's limit for the kind.",
      frame(nack_big, 15, frame_flags::kReply));

  Nack nack_shape;
  nack_shape.request_type = static_cast<uint8_t>(MsgType::XferBegin);
  nack_shape.status = static_cast<uint8_t>(StatusCode::Unsupported);
  nack_shape.field = 2;
  add("nack_xfer_begin_shape", "Protocol 1.2: a model total_size (field 2) no shape of RIG_INFO's list can have.",
      frame(nack_shape, 16, frame_flags::kReply));

  Nack nack_chunk_shape = nack_shape;
  nack_chunk_shape.request_type = static_cast<uint8_t>(MsgType::XferChunk);
  add("nack_xfer_chunk_shape", "Protocol 1.2: the model header in the chunk's data (field 2) names a shape RIG_INFO does not accept.",
      frame(nack_chunk_shape, 17, frame_flags::kReply));

  Nack nack_ident;
  nack_ident.request_type = static_cast<uint8_t>(MsgType::IdentStart);
  nack_ident.status = static_cast<uint8_t>(StatusCode::Inconsistent);
  nack_ident.field = 7;
  add("nack_ident_start_band", "Protocol 1.3: band_hi (field 7) below band_lo.",
      frame(nack_ident, 31, frame_flags::kReply));
  Nack nack_signal = nack_ident;
  nack_signal.status = static_cast<uint8_t>(StatusCode::OutOfRange);
  nack_signal.field = 1;
  add("nack_ident_start_signal",
      "Protocol 1.3: a signal (field 1) the firmware does not have: aprbs (4) at a firmware without it.",
      frame(nack_signal, 33, frame_flags::kReply));

}

void pong_and_info_replies() {
  add("pong", "", frame(handshake_pong(), 1, frame_flags::kReply));

  const Info info = hasel_info();
  add("info_hasel", "Protocol 1.0's reply to INFO_GET; a 1.1 console still reads it.",
      frame(info, 2, frame_flags::kReply));

  InfoEx info_ex;
  info_ex.info = info;
  info_ex.table_max = 776;
  info_ex.model_max = 10240;
  info_ex.protocol_minor = 1;
  add("info_ex_hasel", "Protocol 1.1's reply to INFO_GET: INFO's fields, then the transfer limits and the minor revision.",
      frame(info_ex, 2, frame_flags::kReply));

  InfoEx info_ex12 = info_ex;
  info_ex12.protocol_minor = 2;
  info_ex12.info.capabilities |= capability::kRig;
  add("info_ex_hasel_1_2", "A 1.2 firmware's INFO_EX: the same layout, protocol_minor 2 and the RIG capability (bit 8).",
      frame(info_ex12, 2, frame_flags::kReply));

  InfoEx info_ex13 = info_ex12;
  info_ex13.protocol_minor = 3;
  info_ex13.info.capabilities |= capability::kIdent;
  add("info_ex_hasel_1_3", "A 1.3 firmware's INFO_EX: protocol_minor 3 and the IDENT capability (bit 9).",
      frame(info_ex13, 2, frame_flags::kReply));

  InfoEx info_ex14 = info_ex13;
  info_ex14.protocol_minor = 4;
  info_ex14.info.capabilities |= capability::kIdentMixed | capability::kDevices;
  add("info_ex_hasel_1_4", "A 1.4 firmware's INFO_EX: protocol_minor 4 and the DEVICES capability (bit 11).",
      frame(info_ex14, 2, frame_flags::kReply));

  InfoEx info_ex15 = info_ex14;
  info_ex15.protocol_minor = 5;
  info_ex15.info.capabilities |= capability::kSettings;
  add("info_ex_hasel_1_5", "A 1.5 firmware's INFO_EX: protocol_minor 5 and the SETTINGS capability (bit 12).",
      frame(info_ex15, 2, frame_flags::kReply));
}

void rig_infos() {
  RigInfo rig;
  rig.rig_hash = 0x5A17C0DEu;
  set_text(rig.rig_name, "hasel");
  rig.m = 6, rig.n = 3, rig.w = 18, rig.nd = 2, rig.dd = 2;
  rig.accept = shape_accept::kList;
  rig.max_layers = 4;
  rig.max_width = 5;
  rig.max_weights = 233;
  // Dense 36 -> 5 -> 5 -> 3: L = 3, then (kind 1, units) per layer.
  const uint8_t hasel_shape[] = {3, 1, 5, 0, 1, 5, 0, 1, 3, 0};
  std::memcpy(rig.shapes, hasel_shape, sizeof hasel_shape);
  rig.shapes_size = sizeof hasel_shape;
  add("rig_info_hasel", "An MCU image: exactly one shape, Dense 36->5->5->3 (accept 0, the list).",
      frame(rig, 30, frame_flags::kReply));

  RigInfo rig_tendon;
  set_text(rig_tendon.rig_name, "tendon");
  rig_tendon.m = 2, rig_tendon.n = 3, rig_tendon.w = 11, rig_tendon.nd = 2, rig_tendon.dd = 2;
  rig_tendon.accept = shape_accept::kList;
  rig_tendon.max_layers = 4;
  rig_tendon.max_width = 16;
  rig_tendon.max_weights = 512;
  // GRU(5) -> 5 -> 3 and, a second listed shape, Dense 21 -> 8 -> 3.
  const uint8_t tendon_shapes[] = {3, 2, 5, 0, 1, 5, 0, 1, 3, 0, 2, 1, 8, 0, 1, 3, 0};
  std::memcpy(rig_tendon.shapes, tendon_shapes, sizeof tendon_shapes);
  rig_tendon.shapes_size = sizeof tendon_shapes;
  add("rig_info_two_shapes", "Two listed shapes, a GRU first layer in the first; rig_hash 0: not built from a rig file.",
      frame(rig_tendon, 31, frame_flags::kReply));

  RigInfo rig_any;
  set_text(rig_any.rig_name, "hasel");
  rig_any.m = 6, rig_any.n = 3, rig_any.w = 18, rig_any.nd = 2, rig_any.dd = 2;
  rig_any.accept = shape_accept::kAny;
  rig_any.max_layers = 8;
  rig_any.max_width = 48;
  rig_any.max_weights = 8192;
  add("rig_info_any_shape", "A generic kernel (the simulator): any shape within the limits, an empty list.",
      frame(rig_any, 32, frame_flags::kReply));
}

void param_and_transfer_replies() {
  ParamDesc desc;
  desc.index = 0;
  desc.count = 14;
  desc.id = 3;
  desc.type = static_cast<uint8_t>(ParamType::F32);
  desc.size = 3;
  desc.min = 0.0f;
  desc.max = 1e9f;
  set_text(desc.unit, "");
  set_text(desc.name, "Q");
  add("param_desc_q", "", frame(desc, 3, frame_flags::kReply));

  ParamDesc desc_n;
  desc_n.index = 5;
  desc_n.count = 14;
  desc_n.id = 10;
  desc_n.type = static_cast<uint8_t>(ParamType::U8);
  desc_n.size = 1;
  desc_n.access = param_access::kStoppedOnly;
  desc_n.min = 1.0f;
  desc_n.max = 8.0f;
  set_text(desc_n.unit, "steps");
  set_text(desc_n.name, "N");
  add("param_desc_horizon", "", frame(desc_n, 20, frame_flags::kReply));

  ParamValue pv;
  pv.id = 3;
  pv.type = static_cast<uint8_t>(ParamType::F32);
  pv.count = 3;
  pv.set_f32(0, 1e6f);
  pv.set_f32(1, 2e6f);
  pv.set_f32(2, 1e6f);
  add("param_value_q", "Reply to param_set_vector: the value now in force.",
      frame(pv, 5, frame_flags::kReply));

  ParamValue pv_n;
  pv_n.id = 10;
  pv_n.type = static_cast<uint8_t>(ParamType::U8);
  pv_n.count = 1;
  pv_n.values[0] = 3;
  add("param_value_integer", "", frame(pv_n, 6, frame_flags::kReply));

  XferAck xack;
  xack.kind = static_cast<uint8_t>(XferKind::RefTable);
  xack.next_offset = 256;
  xack.total_size = 1234;
  add("xfer_ack", "Reply to xfer_chunk: the next offset the firmware expects.",
      frame(xack, 11, frame_flags::kReply));
}

void statuses() {
  Status st;
  st.uptime_ms = 60000;
  st.run_id = 42;
  st.step = 7800;
  st.run_state = static_cast<uint8_t>(RunState::Running);
  st.watchdog = watchdog_flags::kArmed;
  st.telemetry_mask = telemetry_field::kAll;
  st.ref_id = static_cast<uint8_t>(RefId::Swirl);
  st.frames_in = 1200;
  st.crc_errors = 2;
  st.frame_errors = 1;
  st.tx_dropped = 0;
  st.loop_overruns = 3;
  st.compute_min = 1800;
  st.compute_mean = 2100;
  st.compute_max = 5400;
  st.tick_rate_hz = 180000000;
  add("status_heartbeat", "Unsolicited heartbeat: REPLY flag clear, firmware's own seq.",
      frame(st, 77));

  Status tripped = st;
  tripped.uptime_ms = 61200;
  tripped.run_state = static_cast<uint8_t>(RunState::Neutral);
  tripped.watchdog = watchdog_flags::kArmed | watchdog_flags::kTripped;
  add("status_watchdog_tripped",
      "The link went silent during run 42: actuators neutral (run_state 3), watchdog bits armed and tripped.",
      frame(tripped, 80));

  Status ident_status = st;
  ident_status.run_id = 43;
  ident_status.run_state = static_cast<uint8_t>(RunState::Ident);
  add("status_ident", "Protocol 1.3: run 43 is an identification run (run_state 5).", frame(ident_status, 82));
}

void telemetry_frames() {
  Telemetry tel;
  tel.tseq = 65535;
  tel.mask = telemetry_field::kAll;
  tel.n = 3;
  tel.m = 6;
  tel.step = 123456;
  tel.time_us = 949996800u;
  const float yref[] = {0.5f, -1.25f, 2.0f};
  const float yhat[] = {0.49f, -1.2f, 1.98f};
  const float ytrue[] = {0.48f, -1.21f, 1.97f};
  for (int i = 0; i < 3; ++i) {
    tel.y_ref[i] = yref[i];
    tel.y_hat[i] = yhat[i];
    tel.y_true[i] = ytrue[i];
  }
  for (int i = 0; i < 6; ++i) tel.u[i] = 0.1f * static_cast<float>(i) - 0.2f;
  tel.cost = 1234.5f;
  tel.iterations = 3;
  tel.compute_ticks = 2100;
  add("telemetry_hasel_all", "Every field, hasel dims (n=3, m=6): 81-byte payload, 90 on the wire.",
      frame(tel, 78));

  add("telemetry_msd_compact", "msd dims (n=1, m=1), step + y_hat + u: 16-byte payload.",
      frame(msd_compact_telemetry(), 79));

  Telemetry tnone;
  tnone.tseq = 2;
  tnone.n = 3;
  tnone.m = 2;
  add("telemetry_empty_mask", "Mask 0: only the telemetry sequence (keeps loss counting alive).",
      frame(tnone, 80));
}

void ident_samples() {
  IdentSample is;
  is.tseq = 300;
  is.m = 6;
  is.n = 3;
  is.w = 18;
  is.step = 1200;
  is.time_us = 9230769u;
  for (int i = 0; i < 6; ++i) is.u[i] = 0.5f * static_cast<float>(i);
  for (int i = 0; i < 3; ++i) is.y[i] = 1.5f - static_cast<float>(i);
  for (int i = 0; i < 18; ++i) is.l[i] = 0.01f * static_cast<float>(i * i) - 0.5f;
  add("ident_sample_hasel", "Protocol 1.3: hasel dims (m=6, n=3, w=18): 121-byte payload, 130 on the wire.",
      frame(is, 83));
  IdentSample is_msd;
  is_msd.tseq = 301;
  is_msd.m = 1;
  is_msd.n = 1;
  is_msd.step = 3;
  is_msd.time_us = 3000;
  is_msd.u[0] = 250.0f;
  is_msd.y[0] = 0.0125f;
  add("ident_sample_msd", "Protocol 1.3: msd (m=1, n=1, no sensors): 21-byte payload, 30 on the wire.",
      frame(is_msd, 84));
  IdentSample is_no_y = is_msd;
  is_no_y.n = 0;
  is_no_y.w = 2;
  is_no_y.l[0] = 0.25f;
  is_no_y.l[1] = -0.75f;
  add("ident_sample_no_output", "Protocol 1.3: n = 0, a firmware that measures no output; u and two sensors.",
      frame(is_no_y, 85));
}

void device_frames() {
  DeviceGet dg;
  dg.index = 1;
  add("device_get", "Protocol 1.4: the state of device 1.", frame(dg, 91));
  DeviceStatus ds;
  ds.index = 0;
  ds.count = 2;
  ds.state = static_cast<uint8_t>(DeviceState::Ok);
  ds.bus = 0;
  ds.address = 0x1E;
  ds.age_ms = 3;
  ds.faults = 0;
  set_text(ds.name, "tip");
  add("device_status_ok", "Protocol 1.4: a magnetometer at 0x1e on bus 0, its latest sample 3 ms old.",
      frame(ds, 90, frame_flags::kReply));
  DeviceStatus absent = ds;
  absent.index = 1;
  absent.state = static_cast<uint8_t>(DeviceState::Absent);
  absent.bus = 1;
  absent.address = 4;  // SPI: chip select number 4
  absent.age_ms = kNoSample;
  absent.faults = 12;
  set_text(absent.name, "ring1");
  add("device_status_absent", "Protocol 1.4: a chip on SPI bus 1, chip select 4, that never answered (age 0xffffffff).",
      frame(absent, 91, frame_flags::kReply));
  DeviceStatus servo = ds;
  servo.index = 1;
  servo.state = static_cast<uint8_t>(DeviceState::Fault);
  servo.bus = 3;      // stm32f4's usart1
  servo.address = 2;  // the servo's id
  servo.age_ms = 40;
  servo.faults = 1;
  set_text(servo.name, "rx64-2");
  add("device_status_servo_fault",
      "Protocol 1.7: servo id 2 on stm32f4's usart1 (bus 3) in fault: it answers, reporting an error of its own.",
      frame(servo, 92, frame_flags::kReply));
  SensorHealth sh;
  sh.step = 1200;
  sh.invalid = 0x00000038u;  // channels 3, 4, 5: one magnetometer's x, y, z
  sh.age_ms = 7;
  add("sensor_health", "Protocol 1.4: sensor channels 3 to 5 invalid at step 1200, the oldest valid sample 7 ms old.",
      frame(sh, 86));
}

void sensor_stream_frames() {
  SensorStream stream_on;
  stream_on.on = 1;
  add("sensor_stream_on", "Protocol 1.6: each closed-loop TELEMETRY from now on preceded by its step's SENSOR_SAMPLE.",
      frame(stream_on, 95));
  Ack stream_ack;
  stream_ack.request_type = static_cast<uint8_t>(MsgType::SensorStream);
  add("sensor_stream_ack", "Protocol 1.6: the ACK of sensor_stream_on.", frame(stream_ack, 95, frame_flags::kReply));
  Nack stream_none;
  stream_none.request_type = static_cast<uint8_t>(MsgType::SensorStream);
  stream_none.status = static_cast<uint8_t>(StatusCode::Unsupported);
  add("sensor_stream_nack_no_sensors",
      "Protocol 1.6: SENSOR_STREAM refused unsupported by the firmware of a rig without sensors (w 0).",
      frame(stream_none, 95, frame_flags::kReply));
  SensorSample ss;
  ss.step = 1200;
  ss.w = 3;
  ss.l[0] = 0.5f;
  ss.l[1] = -1.25f;
  ss.l[2] = 3.0f;
  add("sensor_sample", "Protocol 1.6: the three sensors of closed-loop step 1200, sent right before its TELEMETRY.",
      frame(ss, 87));
}

void settings_frames() {
  struct SettingsVector {
    SettingsAction action;
    const char* name;
    const char* note;
    uint8_t seq;
  };
  for (const SettingsVector& v : {
           SettingsVector{SettingsAction::Save, "settings_save",
                          "Protocol 1.5: save the parameters in force to flash; ACK once the record is written.", 92},
           SettingsVector{SettingsAction::Defaults, "settings_defaults",
                          "Protocol 1.5: the built-in defaults in force again, and at every boot from now on.", 93},
           SettingsVector{SettingsAction::Report, "settings_report",
                          "Protocol 1.5: ACK, then a LOG saying where the settings in force came from.", 94},
       }) {
    Settings req;
    req.action = static_cast<uint8_t>(v.action);
    add(v.name, v.note, frame(req, v.seq));
  }
  Ack settings_ack;
  settings_ack.request_type = static_cast<uint8_t>(MsgType::Settings);
  add("settings_ack", "Protocol 1.5: the ACK of settings_save.", frame(settings_ack, 92, frame_flags::kReply));
  Nack settings_busy;
  settings_busy.request_type = static_cast<uint8_t>(MsgType::Settings);
  settings_busy.status = static_cast<uint8_t>(StatusCode::WrongState);
  settings_busy.field = 0;
  add("settings_nack_running", "Protocol 1.5: SETTINGS refused while a run is active (wrong_state, field 0).",
      frame(settings_busy, 92, frame_flags::kReply));
}

void log_frames() {
  Log log;
  log.level = static_cast<uint8_t>(LogLevel::Warn);
  set_text(log.text, "loop overrun at step 12: \"compute\" took 1.2 ms");
  add("log_warn", "", frame(log, 81));
}

// --------------------------------------------------------------- streams
void streams() {
  const Ping ping = handshake_ping();
  const Pong pong = handshake_pong();
  add("two_frames_back_to_back", "One delimiter between frames is enough.",
      cat({frame(ping, 1), frame(pong, 1, frame_flags::kReply)}));
  add("leading_and_repeated_delimiters",
      "Extra 0x00 bytes are idle: they produce no event and no error.",
      cat({Bytes{0, 0}, frame(ping, 1), Bytes{0, 0, 0}}));
}

// ---------------------------------------------------------------- errors
void damaged_headers_and_crcs() {
  const Ping ping = handshake_ping();
  {
    Bytes raw = raw_frame(ping, 1);
    raw[raw.size() - 1] ^= 0x01;
    add("error_bad_crc", "ping with its CRC's high byte flipped.", cobs_wire(raw));
  }
  {
    Bytes raw = raw_frame(ping, 1);
    raw[6] ^= 0x80;
    add("error_bad_crc_payload_bit", "ping with one payload bit flipped.", cobs_wire(raw));
  }
  {
    Bytes raw = raw_frame(ping, 1);
    reseal(raw, static_cast<uint8_t>(MsgType::RunStart));
    add("error_bad_crc_layout_seed",
        "ping body sealed with RUN_START's CRC seed: a peer with another layout for a type "
        "rejects it.",
        cobs_wire(raw));
  }
  {
    Bytes raw = raw_frame(ping, 1);
    raw.resize(4);
    add("error_truncated_header", "Only 4 bytes: shorter than header + CRC.", cobs_wire(raw));
  }
  {
    Bytes raw = raw_frame(ping, 1);
    raw.resize(raw.size() - 2);
    add("error_truncated_payload",
        "Valid COBS, but 2 bytes fewer than the header's length declares.", cobs_wire(raw));
  }
  {
    Bytes raw = raw_frame(ping, 1);
    raw.push_back(0x42);
    add("error_length_mismatch", "One byte more than the header declares.", cobs_wire(raw));
  }
  {
    Bytes raw = raw_frame(ping, 1);
    raw[0] = 2;
    reseal(raw, static_cast<uint8_t>(MsgType::Ping));
    add("error_wrong_version", "ping from a protocol version 2 peer.", cobs_wire(raw));
  }
  {
    Bytes raw = raw_frame(ping, 1);
    raw[1] = 0x30;
    reseal(raw, 0x30);
    add("error_unknown_type", "Type 0x30 is not in the catalogue.", cobs_wire(raw));
  }
}

void damaged_lengths_and_framing() {
  const Ping ping = handshake_ping();
  const Pong pong = handshake_pong();
  {
    Bytes raw = {kProtocolVersion, static_cast<uint8_t>(MsgType::Ping), 1, 0, 3, 1, 2, 3, 0, 0};
    reseal(raw, static_cast<uint8_t>(MsgType::Ping));
    add("error_bad_length_for_type", "ping with a 3-byte payload; PING needs exactly 4.",
        cobs_wire(raw));
  }
  {
    Bytes raw = raw_frame(msd_compact_telemetry(), 79);
    raw[kHeaderSize + 3] = 0x21;  // dims n=2 m=1: the fields no longer add up
    reseal(raw, static_cast<uint8_t>(MsgType::Telemetry));
    add("error_bad_length_telemetry_dims", "telemetry whose dims byte does not match its length.",
        cobs_wire(raw));
  }
  {
    IdentSample one;
    one.m = 1;
    one.n = 1;
    one.w = 1;
    Bytes raw = raw_frame(one, 86);
    raw[kHeaderSize + 4] = 2;  // w = 2: one sensor value short
    reseal(raw, static_cast<uint8_t>(MsgType::IdentSample));
    add("error_bad_length_ident_sample", "IDENT_SAMPLE whose m, n, w do not add up to its length.",
        cobs_wire(raw));
  }
  {
    Bytes wire = frame(ping, 1);
    wire.erase(wire.end() - 2);
    add("error_cobs", "ping with its last byte lost: the delimiter arrives inside a COBS block.",
        wire);
  }
  {
    Bytes wire(300, 0x55);
    wire.push_back(0);
    add("error_oversize", "300 bytes without a delimiter.", cat({wire, frame(ping, 1)}));
  }
  add("garbage_between_frames",
      "Terminated garbage between two good frames costs one error and no frame.",
      cat({frame(ping, 1), Bytes{0xDE, 0xAD, 0xBE, 0xEF, 0x00}, frame(pong, 1, frame_flags::kReply)}));
  add("garbage_glued_to_frame",
      "Garbage with no delimiter before a frame spoils that frame only; the next one is fine.",
      cat({Bytes{0x13, 0x37, 0x42}, frame(ping, 1), frame(ping, 2)}));
  {
    const Bytes info_wire = frame(hasel_info(), 2, frame_flags::kReply);
    add("frame_cut_by_reset",
        "A frame cut short by a sender reset, then the next frame: one error, then resync.",
        cat({Bytes(info_wire.begin(), info_wire.begin() + 20), Bytes{0x00}, frame(ping, 3)}));
  }
}

// golden.txt's vectors, group by group in the file's order.
void build() {
  for (void (*group)() : {handshake_and_param_requests, ref_and_transfer_requests, run_requests, ident_requests,
                          acks_and_nacks, pong_and_info_replies, rig_infos, param_and_transfer_replies, statuses,
                          telemetry_frames, ident_samples, device_frames, sensor_stream_frames, settings_frames,
                          log_frames, streams, damaged_headers_and_crcs, damaged_lengths_and_framing})
    group();
}

// The golden model file (PROTOCOL.md 9.4, "Model file"), built byte by byte
// from the layout table as a third party would: an msd-sized ARX network,
// y(k+1) = 1.8 y(k) - 0.81 y(k-1) + 0.01 u(k), one linear dense layer.
Bytes golden_model() {
  Bytes f;
  auto u8 = [&](uint8_t v) { f.push_back(v); };
  auto u16 = [&](uint16_t v) { u8(uint8_t(v)), u8(uint8_t(v >> 8)); };
  auto u32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(uint8_t(v >> (8 * i)));
  };
  auto f32 = [&](float x) {
    uint32_t w;
    std::memcpy(&w, &x, 4);
    u32(w);
  };
  const uint8_t m = 1, n = 1, w = 0, nd = 2, dd = 2;
  const uint8_t p = nd * m + dd * n + w;  // 4 inputs: u(k) u(k-1) y(k) y(k-1)
  const uint32_t params = 2u * p + 2u * n + (p * 1u + 1u);
  for (char c : {'N', 'L', 'S', 'M'}) u8(uint8_t(c));
  u8(1);  // format version
  u8(0);  // flags: not residual
  u8(m), u8(n), u8(w), u8(nd), u8(dd);
  u8(1);  // layers
  u32(params);
  u8(0);  // platform msd
  for (int i = 0; i < 7; ++i) u8(0);
  u8(1), u8(0), u8(3), u8(0), u16(p), u16(1);  // dense, linear, (sigmoid), -, in p, out 1
  for (int i = 0; i < p; ++i) f32(0.0f);       // in_offset
  for (int i = 0; i < p; ++i) f32(1.0f);       // in_scale
  f32(0.0f);                                   // out_offset
  f32(1.0f);                                   // out_scale
  for (float x : {0.01f, 0.0f, 1.8f, -0.81f}) f32(x);  // W[in][out]
  f32(0.0f);                                           // b
  u32(crc32(f.data(), f.size()));
  return f;
}

void print_model() {
  const Bytes f = golden_model();
  std::printf(
      "# nlsoft golden model file (PROTOCOL.md 9.4, \"Model file (kind 2)\").\n"
      "# Generated by protocol/tools/gen_vectors.cpp --model, checked in, reviewed by hand.\n"
      "# An msd-sized ARX network, y(k+1) = 1.8 y(k) - 0.81 y(k-1) + 0.01 u(k):\n"
      "#   header  NLSM, version 1, flags 0, m 1, n 1, w 0, nd 2, dd 2, 1 layer, 15 parameters, platform 0\n"
      "#   layer   dense (1), linear (0), rec_act sigmoid (3, unused), reset_after 0, in 4, out 1\n"
      "#   params  in_offset 0 0 0 0 | in_scale 1 1 1 1 | out_offset 0 | out_scale 1 |\n"
      "#           W[4][1] 0.01 0 1.8 -0.81 | b[1] 0\n"
      "#   trailer CRC-32 of every byte before it (INFO.model_hash once in force)\n"
      "# Uploaded as transfer kind 2 to a firmware with m 1, n 1, w 0 (msd) whose\n"
      "# image runs this shape, it is ACKed and INFO.model_hash becomes crc32.\n");
  std::printf("size: %zu\n", f.size());
  const uint32_t crc = uint32_t(f[f.size() - 4]) | uint32_t(f[f.size() - 3]) << 8 | uint32_t(f[f.size() - 2]) << 16 |
                       uint32_t(f[f.size() - 1]) << 24;
  std::printf("crc32: 0x%08x\n", crc);
  for (size_t i = 0; i < f.size(); i += 24) {
    std::printf("file:");
    for (size_t j = i; j < f.size() && j < i + 24; ++j) std::printf(" %02x", f[j]);
    std::printf("\n");
  }
}

void print_hex_lines(const Bytes& b) {
  for (size_t i = 0; i < b.size(); i += 32) {
    std::printf("wire:");
    for (size_t j = i; j < b.size() && j < i + 32; ++j) std::printf(" %02x", b[j]);
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::strcmp(argv[1], "--model") == 0) {
    print_model();
    return 0;
  }
  build();
  std::printf(
      "# nlsoft wire protocol golden vectors (protocol %u.%u; the frames' version byte is %u).\n"
      "# Generated by protocol/tools/gen_vectors.cpp, checked in, reviewed by hand.\n"
      "# Format (PROTOCOL.md, \"Golden vectors\"): blocks separated by blank lines;\n"
      "#   vector: <name>\n"
      "#   note:   <free text>                      (optional, may repeat)\n"
      "#   wire:   <hex bytes, space separated>      (repeats; concatenate all)\n"
      "#   expect: frame <TYPE> seq=<n> flags=<n> <field>=<value> ...\n"
      "#   expect: error <reason>\n"
      "# One expect line per decoder event, in order. Feeding the wire bytes to a\n"
      "# fresh decoder must give exactly these events. When the wire is exactly one\n"
      "# good frame (a single 0x00, at the end), encoding the expected message must\n"
      "# give exactly the wire bytes.\n",
      kProtocolVersion, kProtocolMinor, kProtocolVersion);
  for (const Entry& e : g_entries) {
    std::printf("\nvector: %s\n", e.name.c_str());
    if (!e.note.empty()) std::printf("note: %s\n", e.note.c_str());
    print_hex_lines(e.wire);
    for (const std::string& ev : golden::decode_events(e.wire)) {
      std::printf("expect: %s\n", ev.c_str());
    }
  }
  return 0;
}
