#pragma once
// SETTINGS (PROTOCOL.md 9.11): the parameters in force saved to flash and
// applied again at boot, over the power-cut-safe record of settings_store.hpp.
//
// The record's payload (format 1, little-endian):
//   u16 format (1), u16 entry count, then per parameter
//   u16 id, u8 type (PARAM_DESC's), u8 count, u32[count] words (PARAM_SET's)
// Every entry of the parameter list is saved: the controller's table and
// the firmware's own settings (watchdog_ms, safe_state); the model and the
// reference are not. At boot each entry goes through PARAM_SET's own
// validation (ParamService::set), so a value this build no longer accepts
// (a narrower range, a parameter gone, another element count) is skipped
// and named in the boot LOG, never forced in. An entry refused only for
// its order (Nc > N until N is applied) is tried again after the others.
//
// Caller-owned buffers, no heap, no exceptions.
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "firmware/core/log_text.hpp"
#include "firmware/core/param_service.hpp"
#include "firmware/core/settings_store.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::fw {

// Where the settings in force came from (the boot LOG, SETTINGS report).
enum class SettingsSource : uint8_t {
  NoStore = 0,   // this board keeps no settings: built-in
  Nothing,       // built-in: nothing saved yet (or no record checks)
  Flash,         // the saved record `seq`
  Restored,      // built-in: the defaults restored by request (a length-0 record)
  Saved,         // the values in force were saved just now as record `seq`
  Unreadable,    // built-in: the newest record is of a format this build does not read
};

// What Firmware holds in its place when built without settings.
struct NoSettingsService {
  template <class P>
  explicit NoSettingsService(P&) {}
};

// Payload bytes a parameter list of `params` entries needs at most.
constexpr size_t settings_payload_max(size_t params) { return 4 + params * (4 + 4 * size_t(proto::kMaxParamValues)); }

template <class Cap>
class SettingsService {
 public:
  static constexpr uint16_t kFormat = 1;
  static constexpr size_t kMaxSkipped = 8;  // named in the LOG; more are counted

  explicit SettingsService(ParamService<Cap>& params) : params_(params) {}

  // A store and the buffer of a whole record. Before boot().
  void attach(SettingsStore& store, uint8_t* payload, size_t payload_cap) {
    store_ = &store;
    buf_ = payload, cap_ = payload_cap;
    source_ = SettingsSource::Nothing;
  }
  bool attached() const { return store_ != nullptr; }

  // Applies the newest record, if any; true when a value changed (the
  // caller then reconfigures the controller). The LOG is then pending.
  bool boot() {
    if (!attached()) return false;
    log_pending_ = true;
    SettingsRecord rec;
    if (store_->load(buf_, cap_, rec) != SettingsStatus::Ok) return (source_ = SettingsSource::Nothing), false;
    seq_ = rec.seq;
    if (rec.length == 0) return (source_ = SettingsSource::Restored), false;
    if (rec.length < 4 || get16(buf_) != kFormat) return (source_ = SettingsSource::Unreadable), false;
    source_ = SettingsSource::Flash;
    return apply(rec.length);
  }

  // SETTINGS save: every parameter's value in force as the newest record.
  proto::StatusCode save() {
    if (!attached()) return proto::StatusCode::Unsupported;
    size_t len = 4, entries = 0;
    for (uint16_t i = 0; i < ParamService<Cap>::count(); ++i) {
      proto::ParamDesc d;
      if (!params_.describe(i, d) || (d.access & proto::param_access::kReadOnly)) continue;
      const ParamReply r = params_.get(d.id);
      if (r.status != proto::StatusCode::Ok) continue;
      if (len + 4 + 4u * r.value.count > cap_) return proto::StatusCode::TooLarge;
      put16(buf_ + len, d.id);
      buf_[len + 2] = r.value.type;
      buf_[len + 3] = r.value.count;
      len += 4;
      for (uint8_t k = 0; k < r.value.count; ++k, len += 4) put32(buf_ + len, r.value.values[k]);
      ++entries;
    }
    put16(buf_, kFormat);
    put16(buf_ + 2, uint16_t(entries));
    const proto::StatusCode s = write(len);
    if (s != proto::StatusCode::Ok) return s;
    source_ = SettingsSource::Saved;
    values_ = uint16_t(entries);
    skipped_ = 0;
    return s;
  }

  // SETTINGS defaults: a record that says "built-in" (the caller puts the
  // built-in values in force once this succeeds).
  proto::StatusCode restore_defaults() {
    if (!attached()) return proto::StatusCode::Unsupported;
    const proto::StatusCode s = write(0);
    if (s == proto::StatusCode::Ok) source_ = SettingsSource::Restored, values_ = 0, skipped_ = 0;
    return s;
  }

  SettingsSource source() const { return source_; }
  uint32_t seq() const { return seq_; }
  uint16_t values() const { return values_; }
  uint16_t skipped() const { return skipped_; }

  // The LOG that says where the settings in force came from: pending from
  // boot until the first request arrives (a console may connect long after
  // the boot), and again after each SETTINGS.
  bool log_pending() const { return log_pending_; }
  void log_sent() { log_pending_ = false; }
  void log_again() { log_pending_ = attached(); }
  proto::LogLevel log_level() const {
    return skipped_ > 0 || source_ == SettingsSource::Unreadable ? proto::LogLevel::Warn : proto::LogLevel::Info;
  }
  template <size_t N>
  void describe(LogText<N>& t) const {
    switch (source_) {
      case SettingsSource::NoStore: t << "settings: built-in (this board keeps no settings)"; return;
      case SettingsSource::Nothing: t << "settings: built-in (nothing saved)"; return;
      case SettingsSource::Restored: t << "settings: built-in (restored by request)"; return;
      case SettingsSource::Unreadable:
        t << "settings: built-in (save " << seq_ << " is of a format this firmware does not read)";
        return;
      case SettingsSource::Saved: t << "settings: saved to flash, save " << seq_ << " (" << uint32_t(values_) << " values)"; return;
      case SettingsSource::Flash: break;
    }
    t << "settings: from flash, save " << seq_ << " (" << uint32_t(values_) << " values";
    if (skipped_ > 0) {
      t << "; " << uint32_t(skipped_) << " skipped, not accepted by this firmware:";
      for (size_t i = 0; i < skipped_ && i < kMaxSkipped; ++i)
        t << " id " << uint32_t(skip_id_[i]) << " (" << status_word(skip_status_[i]) << ")";
      if (skipped_ > kMaxSkipped) t << " ...";
    }
    t << ")";
  }

 private:
  proto::StatusCode write(size_t len) {
    SettingsRecord saved;
    const SettingsStatus s = store_->save(buf_, uint32_t(len), &saved);
    if (s == SettingsStatus::TooLarge) return proto::StatusCode::TooLarge;
    if (s != SettingsStatus::Ok) return proto::StatusCode::Internal;
    seq_ = saved.seq;
    return proto::StatusCode::Ok;
  }

  // Each entry through PARAM_SET's validation; the ones refused only for
  // the order they came in (inconsistent: Nc above an N not applied yet)
  // again after the rest, as long as a round applies something.
  bool apply(size_t len) {
    static constexpr uint16_t kMaxEntries = 256;
    uint32_t done[kMaxEntries / 32] = {};  // one bit per entry: applied or skipped
    const uint16_t entries = get16(buf_ + 2);
    const uint16_t n = entries > kMaxEntries ? kMaxEntries : entries;
    bool changed = false, progress = true;
    values_ = 0, skipped_ = 0;
    while (progress) {
      progress = false;
      size_t at = 4;
      for (uint16_t e = 0; e < n && at + 4 <= len; ++e) {
        proto::ParamSet p;
        p.id = get16(buf_ + at);
        const uint8_t type = buf_[at + 2];
        p.count = buf_[at + 3];
        const size_t next = at + 4 + 4u * p.count;
        if (next > len) break;  // a record cut short cannot pass its CRC; this is for a buggy writer
        if (!(done[e / 32] >> (e % 32) & 1u)) {
          proto::StatusCode s;
          if (p.count > proto::kMaxParamValues) {
            s = proto::StatusCode::WrongSize;
          } else {
            for (uint8_t k = 0; k < p.count; ++k) p.values[k] = get32(buf_ + at + 4 + 4u * k);
            const ParamReply now = params_.get(p.id);
            // Another type of parameter under this id now: its words mean something else.
            s = now.status == proto::StatusCode::Ok && now.value.type != type ? proto::StatusCode::BadFormat
                                                                                : params_.set(p).status;
          }
          if (s != proto::StatusCode::Inconsistent) {
            done[e / 32] |= 1u << (e % 32);
            if (s == proto::StatusCode::Ok)
              ++values_, changed = true, progress = true;
            else
              skip(p.id, s);
          }
        }
        at = next;
      }
    }
    // What is left was inconsistent in every round.
    size_t at = 4;
    for (uint16_t e = 0; e < n && at + 4 <= len; ++e) {
      const uint16_t id = get16(buf_ + at);
      at += 4 + 4u * buf_[at + 3];
      if (!(done[e / 32] >> (e % 32) & 1u)) skip(id, proto::StatusCode::Inconsistent);
    }
    return changed;
  }

  void skip(uint16_t id, proto::StatusCode s) {
    if (skipped_ < kMaxSkipped) skip_id_[skipped_] = id, skip_status_[skipped_] = s;
    ++skipped_;
  }

  static const char* status_word(proto::StatusCode s) {
    switch (s) {
      case proto::StatusCode::OutOfRange: return "out of range";
      case proto::StatusCode::NotFinite: return "not finite";
      case proto::StatusCode::WrongSize: return "wrong size";
      case proto::StatusCode::UnknownId: return "unknown id";
      case proto::StatusCode::Inconsistent: return "inconsistent";
      case proto::StatusCode::TooLarge: return "too large";
      case proto::StatusCode::BadFormat: return "another type";
      case proto::StatusCode::ReadOnly: return "read only";
      default: return "refused";
    }
  }

  static void put16(uint8_t* p, uint16_t v) { p[0] = uint8_t(v), p[1] = uint8_t(v >> 8); }
  static void put32(uint8_t* p, uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = uint8_t(v >> (8 * i));
  }
  static uint16_t get16(const uint8_t* p) { return uint16_t(p[0] | p[1] << 8); }
  static uint32_t get32(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
  }

  ParamService<Cap>& params_;
  SettingsStore* store_ = nullptr;
  uint8_t* buf_ = nullptr;
  size_t cap_ = 0;
  SettingsSource source_ = SettingsSource::NoStore;
  uint32_t seq_ = 0;
  uint16_t values_ = 0, skipped_ = 0;
  uint16_t skip_id_[kMaxSkipped] = {};
  proto::StatusCode skip_status_[kMaxSkipped] = {};
  bool log_pending_ = false;
};

}  // namespace nlsoft::fw
