#include "app/conformance/suite.hpp"

#include <fmt/format.h>

#include <cstring>

namespace nlsoft::console::conformance {

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string o;
  for (size_t i = 0; i < v.size(); ++i) o += (i ? sep : "") + v[i];
  return o;
}

float word_f32(uint32_t w) {
  float x;
  std::memcpy(&x, &w, 4);
  return x;
}

uint32_t f32_word(float x) {
  uint32_t w;
  std::memcpy(&w, &x, 4);
  return w;
}

std::string words_text(const uint32_t* v, uint8_t count, uint8_t type) {
  std::string s;
  for (uint8_t i = 0; i < count; ++i) {
    if (i) s += ' ';
    s += type == uint8_t(p::ParamType::F32) ? fmt::format("{:g}", word_f32(v[i])) : fmt::format("{}", v[i]);
  }
  return s;
}

bool Suite::offers(uint32_t capability, const char* cap_name, int since_minor, const std::string& check_name,
                   const char* nothing_to_check) {
  if (info.info.capabilities & capability) return true;
  const bool older = info.protocol_minor < since_minor;
  check(check_name, older,
        fmt::format("protocol 1.{} without the {} capability{}", info.protocol_minor, cap_name,
                    older ? fmt::format(": {}", nothing_to_check) : fmt::format(" (1.{} requires it)", since_minor)));
  return false;
}

void Suite::left_out(const std::string& check_name, const char* service, const Frame& reply, uint8_t field) {
  check(check_name, nacked(reply, p::StatusCode::Unsupported, field, p::kNoField),
        fmt::format("left out of this image ({}): {}", service, describe(reply)));
}

void Suite::check(const std::string& name, bool pass, const std::string& detail) {
  results_.push_back({group_, name, pass, detail});
  if (on_result_) on_result_(results_.back());
}

std::optional<p::Status> Suite::status() {
  const Frame f = pr.request(p::StatusGet{});
  p::Status s;
  if (!as(f, s)) return std::nullopt;
  return s;
}

std::optional<p::InfoEx> Suite::info_now() {
  p::InfoEx x;
  if (!as_info(pr.request(p::InfoGet{}), x)) return std::nullopt;
  return x;
}

std::optional<p::ParamValue> Suite::get(uint16_t id) {
  p::ParamGet g;
  g.id = id;
  const Frame f = pr.request(g);
  p::ParamValue v;
  if (!as(f, v)) return std::nullopt;
  return v;
}

const p::ParamDesc* Suite::param(const char* name) const {
  for (const p::ParamDesc& d : descs)
    if (std::strcmp(d.name, name) == 0 && original.count(d.id)) return &d;
  return nullptr;
}

std::optional<p::ParamValue> Suite::set(const p::ParamDesc& d, const std::vector<uint32_t>& words, std::string& why) {
  p::ParamSet s;
  s.id = d.id;
  s.count = uint8_t(words.size());
  std::copy(words.begin(), words.end(), s.values);
  touched.insert(d.id);
  const Frame f = pr.request(s);
  p::ParamValue v;
  if (as(f, v)) return v;
  why = describe(f);
  return std::nullopt;
}

void Suite::restore_params() {
  std::vector<std::string> bad;
  for (uint16_t id : touched) {
    const p::ParamValue& orig = original.at(id);
    p::ParamSet s;
    s.id = id;
    s.count = orig.count;
    std::memcpy(s.values, orig.values, 4u * orig.count);
    try {
      pr.request(s);
      const auto back = get(id);
      if (!back || back->count != orig.count || std::memcmp(back->values, orig.values, 4u * orig.count) != 0)
        bad.push_back(fmt::format("id {}", id));
    } catch (const LinkError& e) {
      bad.push_back(fmt::format("id {}: {}", id, e.what()));
    }
  }
  group("params");
  check("params_restored", bad.empty(),
        bad.empty() ? fmt::format("{} parameter{} set back and read back", touched.size(), touched.size() == 1 ? "" : "s")
                    : "not restored: " + join(bad, ", "));
  touched.clear();
}

void Suite::run(std::chrono::seconds patience) {
  group("handshake");
  check_handshake(*this, patience);
  try {
    check_basics(*this);
    check_params(*this);
    check_references(*this);
    check_framing(*this);
    check_run_control(*this);
    check_telemetry_rate(*this);
    check_watchdog(*this);
    check_transfers(*this);
    check_rig(*this);
    check_ident(*this);
    check_devices(*this);
    check_settings(*this);
    check_sensor_stream(*this);
  } catch (const LinkError& e) {
    // Whether the device answers again tells a lasting fault from a pause
    // (a board that rebooted, an emulator its host stopped scheduling).
    if (on_link_error_) on_link_error_(e.what());
    std::string after;
    try {
      pr.request(p::RunStop{});
      after = "; afterwards the device answered RUN_STOP";
      restore_params();
    } catch (const LinkError&) {
      if (after.empty()) after = "; afterwards RUN_STOP got no reply either";
    }
    throw LinkError(e.what() + after);
  }
  restore_params();

  group("summary");
  // Every request of the catalogue was answered as section 6 says, and
  // every firmware message was seen at least once.
  std::vector<std::string> missing;
  const std::set<uint8_t> seen = pr.types_seen();
  const std::set<uint8_t> requests_answered = pr.answered();
  const bool rig = (info.info.capabilities & p::capability::kRig) != 0;
  for (const p::MsgInfo& m : p::kMessages) {
    const uint8_t t = uint8_t(m.type);
    // RIG_GET and RIG_INFO are protocol 1.2's, offered with the RIG capability.
    if (!rig && (m.type == p::MsgType::RigGet || m.type == p::MsgType::RigInfo)) continue;
    // IDENT_START and IDENT_SAMPLE are protocol 1.3's, offered with the IDENT capability.
    if (!(info.info.capabilities & p::capability::kIdent) &&
        (m.type == p::MsgType::IdentStart || m.type == p::MsgType::IdentSample))
      continue;
    // DEVICE_GET is protocol 1.4's, with the DEVICES capability; a firmware
    // without chips answers it with the NACK device_list checked and sends
    // no DEVICE_STATUS or SENSOR_HEALTH.
    const bool device_message = m.type == p::MsgType::DeviceGet || m.type == p::MsgType::DeviceStatus ||
                                m.type == p::MsgType::SensorHealth;
    if (device_message && (!(info.info.capabilities & p::capability::kDevices) || devices == 0)) continue;
    // SETTINGS is protocol 1.5's, with the SETTINGS capability (optional: a board without a settings store).
    if (m.type == p::MsgType::Settings && !(info.info.capabilities & p::capability::kSettings)) continue;
    // SENSOR_STREAM and SENSOR_SAMPLE are protocol 1.6's, with the
    // SENSOR_STREAM capability (a rig with sensors).
    if ((m.type == p::MsgType::SensorStream || m.type == p::MsgType::SensorSample) &&
        !(info.info.capabilities & p::capability::kSensorStream))
      continue;
    // An image without either transfer (9.12) refuses XFER_BEGIN, as the
    // transfers group checked, and has no transfer to answer the others in.
    const bool xfer = m.type == p::MsgType::XferBegin || m.type == p::MsgType::XferChunk ||
                      m.type == p::MsgType::XferCommit || m.type == p::MsgType::XferAbort ||
                      m.type == p::MsgType::XferAck;
    if (xfer && !(info.info.capabilities & (p::capability::kXferRefTable | p::capability::kXferModel))) continue;
    if (m.is_request) {
      if (!requests_answered.count(t)) missing.push_back(std::string(m.name) + " never answered");
    } else if (t != uint8_t(p::MsgType::Info) && t != uint8_t(p::MsgType::InfoEx) && !seen.count(t)) {
      missing.push_back(std::string(m.name) + " never seen");
    }
  }
  if (!seen.count(uint8_t(p::MsgType::Info)) && !seen.count(uint8_t(p::MsgType::InfoEx)))
    missing.push_back("INFO never seen");
  check("every_message", missing.empty(),
        missing.empty() ? fmt::format("{} request types answered, {} firmware message types seen",
                                      requests_answered.size(), seen.size())
                        : join(missing, "; "));
  const unsigned foreign = pr.foreign_replies();
  // Not a fault: a retry is the protocol's remedy for a lost frame or a
  // stalled host; but a count well above zero says the line or the host is.
  const Probe::Late late = pr.late();
  const std::string retried =
      late.requests == 0 ? ""
                         : fmt::format("; {} request{} answered only after a retry (longest wait {} ms, for {})",
                                       late.requests, late.requests == 1 ? "" : "s", late.longest.count(),
                                       late.longest_request);
  check("reply_seq", foreign == 0,
        foreign == 0 ? fmt::format("{} replies, each with the seq of a request of ours and REPLY set{}", pr.replies(),
                                   retried)
                     : fmt::format("{} of {} replies answer no request of ours; first: {}{}", foreign, pr.replies(),
                                   pr.first_foreign(), retried));
}

std::string state_of(const std::optional<p::Status>& st) {
  return st ? fmt::format("run_state {} watchdog 0x{:02x} step {}", st->run_state, st->watchdog, st->step)
            : "no STATUS";
}

bool in_state(const std::optional<p::Status>& st, p::RunState state) { return st && st->run_state == uint8_t(state); }

}  // namespace nlsoft::console::conformance
