#pragma once
// PARAM_LIST / PARAM_GET / PARAM_SET (PROTOCOL.md 9.2) over the controller's
// parameter table (shared/params.hpp) plus the firmware's own settings. Every
// write is validated in full before anything changes, and the reply carries
// the value actually in force. The caller hands a changed set to the
// controller between control steps.
#include <cmath>
#include <cstring>

#include "protocol/crc.hpp"
#include "protocol/messages.hpp"
#include "shared/firmware_settings.hpp"
#include "shared/params.hpp"

namespace nlsoft::fw {

namespace proto = nlsoft::protocol;

using nlsoft::FwParamId;
using nlsoft::FwSettings;

struct ParamReply {
  proto::StatusCode status = proto::StatusCode::Ok;
  uint8_t field = proto::kNoField, element = proto::kNoField;
  proto::ParamValue value;
};

template <class Cap>
class ParamService {
 public:
  static constexpr uint16_t kFwCount = 2;
  static constexpr uint16_t count() { return uint16_t(ParamId::Count) + kFwCount; }

  // P: the parameter set in force; m, n: the platform's dimensions.
  ParamService(Params<Cap>& P, int m, int n, FwSettings& fw) : P_(P), m_(m), n_(n), fw_(fw) {}

  bool describe(uint16_t index, proto::ParamDesc& d) const {
    if (index >= count()) return false;
    d = proto::ParamDesc{};
    d.index = index;
    d.count = count();
    if (index < uint16_t(ParamId::Count)) {
      const ParamDesc& p = kParamTable[index];
      d.id = index;
      d.type = uint8_t(p.type);
      d.size = uint8_t(param_count(p, m_, n_));
      d.min = p.min;
      d.max = p.max;
      copy_text(d.unit, p.unit, proto::kUnitLen);
      copy_text(d.name, p.name, proto::kMaxNameLen);
      return true;
    }
    if (index == uint16_t(ParamId::Count)) {
      d.id = uint16_t(FwParamId::WatchdogMs);
      d.type = uint8_t(proto::ParamType::U16);
      d.size = 1;
      d.min = 0.0f;
      d.max = 60000.0f;
      copy_text(d.unit, "ms", proto::kUnitLen);
      copy_text(d.name, "watchdog_ms", proto::kMaxNameLen);
    } else {
      d.id = uint16_t(FwParamId::SafeState);
      d.type = uint8_t(proto::ParamType::Enum);
      d.size = 1;
      d.min = 0.0f;
      d.max = 1.0f;
      copy_text(d.name, "safe_state", proto::kMaxNameLen);
    }
    return true;
  }

  // INFO.param_hash: the CRC-32 of every PARAM_DESC payload in index order,
  // i.e. of the very list a console would read and cache. Platforms differ
  // in their element counts (diag(Q) has n elements), so their hashes do.
  uint32_t hash() const {
    proto::Crc32 crc;
    for (uint16_t i = 0; i < count(); ++i) {
      proto::ParamDesc d;
      uint8_t payload[proto::kMaxPayload];
      size_t len = 0;
      if (!describe(i, d) || proto::pack(d, payload, sizeof payload, len) != proto::StatusCode::Ok) continue;
      crc.update(payload, len);
    }
    return crc.value();
  }

  ParamReply get(uint16_t id) const {
    ParamReply r;
    if (!read(id, r.value)) r.status = proto::StatusCode::UnknownId, r.field = 0;
    return r;
  }

  ParamReply set(const proto::ParamSet& m) {
    ParamReply r;
    proto::ParamDesc d;
    const uint16_t index = index_of(m.id);
    if (index == 0xFFFF || !describe(index, d)) return nack(r, proto::StatusCode::UnknownId, 0, proto::kNoField);
    if (m.count != d.size) return nack(r, proto::StatusCode::WrongSize, 1, proto::kNoField);
    float v[proto::kMaxParamValues];
    for (uint8_t i = 0; i < m.count; ++i) {
      if (d.type == uint8_t(proto::ParamType::F32)) {
        v[i] = m.f32(i);
        if (!std::isfinite(v[i])) return nack(r, proto::StatusCode::NotFinite, 1, i);
      } else {
        if (m.values[i] > 0xFFFFu) return nack(r, proto::StatusCode::OutOfRange, 1, i);
        v[i] = float(m.values[i]);
      }
    }
    if (m.id < uint16_t(ParamId::Count)) {
      const ParamResult pr = set_param(P_, ParamId(m.id), v, m.count, m_, n_);
      if (pr.status != Status::Ok)
        return nack(r, proto::StatusCode(uint8_t(pr.status)), 1, pr.index < 0 ? proto::kNoField : uint8_t(pr.index));
    } else {
      if (v[0] < d.min || v[0] > d.max) return nack(r, proto::StatusCode::OutOfRange, 1, 0);
      if (m.id == uint16_t(FwParamId::WatchdogMs)) fw_.watchdog_ms = uint16_t(v[0]);
      if (m.id == uint16_t(FwParamId::SafeState)) fw_.safe_state = uint8_t(v[0]);
    }
    read(m.id, r.value);
    return r;
  }

 private:
  static ParamReply& nack(ParamReply& r, proto::StatusCode s, uint8_t field, uint8_t element) {
    r.status = s, r.field = field, r.element = element;
    return r;
  }
  static uint16_t index_of(uint16_t id) {
    if (id < uint16_t(ParamId::Count)) return id;
    if (id == uint16_t(FwParamId::WatchdogMs)) return uint16_t(ParamId::Count);
    if (id == uint16_t(FwParamId::SafeState)) return uint16_t(ParamId::Count) + 1;
    return 0xFFFF;
  }
  static void copy_text(char* dst, const char* src, size_t cap) {
    size_t i = 0;
    for (; src[i] && i < cap; ++i) dst[i] = src[i];
    dst[i] = '\0';
  }

  bool read(uint16_t id, proto::ParamValue& out) const {
    out = proto::ParamValue{};
    out.id = id;
    if (id < uint16_t(ParamId::Count)) {
      const ParamDesc& p = kParamTable[id];
      float v[proto::kMaxParamValues];
      const int c = get_param(P_, ParamId(id), m_, n_, v);
      out.type = uint8_t(p.type);
      out.count = uint8_t(c);
      for (int i = 0; i < c; ++i) {
        if (p.type == ParamType::F32)
          out.set_f32(uint8_t(i), v[i]);
        else
          out.values[i] = uint32_t(v[i]);
      }
      return true;
    }
    out.count = 1;
    if (id == uint16_t(FwParamId::WatchdogMs)) {
      out.type = uint8_t(proto::ParamType::U16);
      out.values[0] = fw_.watchdog_ms;
      return true;
    }
    if (id == uint16_t(FwParamId::SafeState)) {
      out.type = uint8_t(proto::ParamType::Enum);
      out.values[0] = fw_.safe_state;
      return true;
    }
    return false;
  }

  Params<Cap>& P_;
  int m_, n_;
  FwSettings& fw_;
};

}  // namespace nlsoft::fw
