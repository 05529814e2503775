#pragma once
// The firmware core, the same on every port: the fixed-rate control step
// (read sensors -> build the input vector -> Newton-Raphson -> clamp ->
// actuate -> telemetry) and the protocol service between steps (requests,
// transfers, heartbeat, watchdog). Static memory only: the port hands in
// every buffer, sized for its target.
#include <cstdio>
#include <cstring>

#include "firmware/core/clock.hpp"
#include "firmware/core/compute_stats.hpp"
#include "firmware/core/hal.hpp"
#include "firmware/core/ident_run.hpp"
#include "firmware/core/log_text.hpp"
#include "firmware/core/model_slot.hpp"
#include "firmware/core/param_service.hpp"
#include "firmware/core/reference_slot.hpp"
#include "firmware/core/rig_reply.hpp"
#include "firmware/core/sensor_sampler.hpp"
#include "firmware/core/settings_service.hpp"
#include "firmware/core/tx_queue.hpp"
#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"
#include "protocol/messages.hpp"
#include "protocol/reply_cache.hpp"
#include "protocol/transfer.hpp"
#include "shared/firmware_features.hpp"
#include "shared/rig_config.hpp"

namespace nlsoft::fw {

namespace proto = nlsoft::protocol;

namespace watchdog_bits = proto::watchdog_flags;

// INFO's platform byte is the rig's PlatformId as it is (uint8_t(rig_.platform)
// below): the two enumerations are one numbering, checked here where both meet.
static_assert(uint8_t(PlatformId::Msd) == uint8_t(proto::Platform::Msd) &&
                  uint8_t(PlatformId::Hasel) == uint8_t(proto::Platform::Hasel) &&
                  uint8_t(PlatformId::Tendon) == uint8_t(proto::Platform::Tendon) &&
                  uint8_t(PlatformId::Custom) == uint8_t(proto::Platform::Custom),
              "PlatformId and protocol::Platform number the rigs alike");

struct Identity {
  const RigConfig* rig;  // the port's, alive as long as the firmware
  const char* name;  // e.g. "nlsoft-posix"
  uint8_t major, minor, patch;
  uint32_t loop_rate_hz;
  bool has_y_true;  // the port reads the true output (a simulated plant, or outputs wired to the board)
};

// Caller-owned memory, sized by the port.
struct Buffers {
  uint8_t* model_staging;  // a whole model file in transit, then the uploaded model in force (4-byte aligned)
  size_t model_staging_cap;
  uint8_t* table_staging;  // a whole reference table in transit
  size_t table_staging_cap;
  float* table_points;     // the table in force
  uint32_t table_points_cap;
};

// Features (shared/firmware_features.hpp): the services the image is built
// with beyond the minimum. Without feature::kChips (a rig without
// [[device]]) it has none of the sampler's code (2.8 kB of flash); without
// kSettings none of the settings service's (about 4 kB on stm32f4); without
// kIdent, kModelUpload, kTableUpload none of those requests' handling. The
// rig's own `features` (RigConfig) narrows them at run time: the simulator,
// built with all, serves what the rig file asks for.
constexpr uint32_t kDefaultFeatures = feature::kIdent | feature::kModelUpload | feature::kTableUpload;
static_assert(firmware_feature(feature::kIdent)->capabilities ==
                      (proto::capability::kIdent | proto::capability::kIdentMixed) &&
                  firmware_feature(feature::kModelUpload)->capabilities == proto::capability::kXferModel &&
                  firmware_feature(feature::kTableUpload)->capabilities == proto::capability::kXferRefTable &&
                  firmware_feature(feature::kSettings)->capabilities == proto::capability::kSettings,
              "shared/firmware_features.hpp's capability bits are protocol/messages.hpp's");

template <class Cap, size_t TxCapacity = 1024, uint32_t Features = kDefaultFeatures>
class Firmware {
  static constexpr bool Chips = (Features & feature::kChips) != 0;
  static constexpr bool Settings = (Features & feature::kSettings) != 0;

 public:
  Firmware(Hal& hal, const Identity& id, const Buffers& b)
      : hal_(hal),
        id_(id),
        rig_(*id.rig),
        params_svc_(params_, rig_.m, rig_.n, settings_),
        ref_(b.table_points, b.table_points_cap),
        model_(rig_, params_, b.model_staging, b.model_staging_cap),
        model_rx_(uint8_t(proto::XferKind::Model), b.model_staging, b.model_staging_cap),
        table_rx_(uint8_t(proto::XferKind::RefTable), b.table_staging, table_max(b)) {
    if (!id.has_y_true) mask_ &= uint8_t(~proto::telemetry_field::kYTrue);
  }

  // The rig's sensor chips, sampled between steps (a board with [[device]]
  // tables); before begin(), which starts them.
  void attach_sensors(SensorSampler& sensors) {
    static_assert(Chips, "an image built without sensor chips has no sampler to attach");
    sensors_ = &sensors;
  }

  // Settings that survive a power cycle (SETTINGS, PROTOCOL.md 9.11): the
  // store over two flash sectors the port reserves, and a buffer of
  // settings_payload_max(ParamService<Cap>::count()) bytes. Before
  // begin(), which applies the newest record; without it the firmware
  // has no SETTINGS capability.
  void attach_settings(SettingsStore& store, uint8_t* payload, size_t payload_cap) {
    static_assert(Settings, "an image built without settings has no service to attach a store to");
    if (rig_.features & feature::kSettings) settings_svc_.attach(store, payload, payload_cap);
  }

  // Loads the compiled-in model (may be null: the firmware then waits for an
  // upload) and the platform's preset parameters, then the saved settings.
  Status begin(const uint8_t* model_file, size_t model_len) {
    clock_.start(hal_.ticks(), hal_.tick_rate_hz());
    last_heartbeat_ms_ = 0;
    Status s = rig_params(rig_, params_);
    if (s != Status::Ok) return s;
    param_hash_ = params_svc_.hash();
    neutral(u_);
    // Until the console selects one, a run follows the rig's own task.
    ref_.select(rig_.reference);
    if (chips()) sensors_->begin(clock_.ms());
    const Status m = model_file ? model_.begin(model_file, model_len) : Status::Ok;
    if (m != Status::Ok) return m;
    if constexpr (Settings) {
      if (settings_svc_.boot()) model_.reconfigure();
    }
    return Status::Ok;
  }

  // The largest table object worth receiving: one that fits the staging
  // buffer and whose points fit the table in force. INFO_EX advertises it,
  // and XFER_BEGIN refuses anything larger as too_large.
  static size_t table_max(const Buffers& b) {
    const size_t by_points = 8 + 4 * size_t(b.table_points_cap);
    return b.table_staging_cap < by_points ? b.table_staging_cap : by_points;
  }

  // Serves the link; call as often as possible between control steps.
  void poll() {
    clock_.update(hal_.ticks());
    uint8_t in[64];
    size_t got;
    while ((got = hal_.serial_read(in, sizeof in)) > 0) {
      size_t used = 0;
      while (used < got) {
        proto::DecodeResult r;
        used += decoder_.feed(in + used, got - used, r);
        if (r.kind == proto::DecodeResult::Kind::Frame) handle(r.frame);
      }
    }
    // Where the settings came from, once a console has spoken (a LOG sent
    // at boot would reach nobody), and again after each SETTINGS.
    if constexpr (Settings) {
      if (settings_svc_.log_pending() && decoder_.stats().frames_ok > 0) settings_log();
    }
    if (chips()) {
      sensors_->poll(clock_.ms());
      report_devices();
    }
    if (clock_.ms() - last_heartbeat_ms_ >= 1000) {
      last_heartbeat_ms_ = clock_.ms();
      send_status(0, false);
    }
    tx_.drain(hal_);
  }

  // One control period. The port calls it at loop_rate_hz (or back to back
  // in fast mode) and reports late calls with count_overrun().
  void step() {
    const uint32_t t0 = hal_.ticks();
    clock_.update(t0);
    const int m = rig_.m, n = rig_.n;
    // A port fills all w sensors; l_ is a member, zeroed once, not a
    // local zeroed every step (newlib-nano's memset goes byte by byte).
    read_sensors(l_);
    have_y_true_ = id_.has_y_true && hal_.read_output(y_true_, n);
    watchdog_check();

    if constexpr ((Features & feature::kIdent) != 0) {
      if (state_ == proto::RunState::Ident || (ident_.active() && state_ != proto::RunState::Idle))
        return ident_step(t0, l_);
    }
    if (state_ != proto::RunState::Running) {
      if (state_ != proto::RunState::Hold) neutral(u_);
      hal_.actuate(u_, m);
      tx_.drain(hal_);
      return;
    }
    float ref[Cap::N * Cap::n];
    ref_.rows(ref, params_.N, n);
    // Built in place: the controller writes only the fields it fills.
    const StepResult<Cap> r = model_.controller().step(ref, l_, have_y_true_ ? y_true_ : nullptr);
    for (int i = 0; i < m; ++i) u_[i] = r.u[i];
    ref_.advance();
    hal_.actuate(u_, m);
    const uint32_t compute = hal_.ticks() - t0;
    stats_.add(compute);
    // A sample is one instant (PROTOCOL.md 9.6): the output measured now
    // beside the reference the last step aimed it at and the prediction it
    // made of it. The first step of a run (or after a resume) had no last
    // step: it sends its own aim and prediction, one step ahead.
    if (!aimed_) aim(ref, r);
    if (decimation_ != 0 && step_ % decimation_ == 0) send_telemetry(r, compute);
    aim(ref, r);
    ++step_;
    tx_.drain(hal_);
  }

  // RIG_INFO accept 0 with the capacity's shapes for this rig even where
  // the kernel is generic: a simulator that stands in for an MCU image, so
  // a console's refusals before XFER_BEGIN can be tried. Before begin().
  void serve_shape_list() { shape_list_ = true; }
  proto::RigInfo rig_info_now() const { return rig_info<Cap>(rig_.name, rig_.hash, rig_, shape_list_); }

  void count_overrun() { ++overruns_; }
  // Fast mode paces itself on this: a step would otherwise drop telemetry.
  bool telemetry_has_room() const {
    return tx_.room() >= TxQueue<TxCapacity>::kReserve + proto::kWireBufferSize;
  }
  proto::RunState state() const { return state_; }
  uint32_t tx_dropped() const { return tx_dropped_; }
  uint32_t frames_in() const { return decoder_.stats().frames_ok; }  // STATUS frames_in

 private:
  // ------------------------------------------------- identification run
  // Open loop (protocol 9.9): the signal's u goes to the actuators; hold and
  // neutral (RUN_HOLD, the watchdog's safe state) pause the signal.
  void ident_step(uint32_t t0, const float* l) {
    const int m = rig_.m;
    const bool driving = state_ == proto::RunState::Ident;
    if (driving) {
      ident_.next(u_, params_.u_min, params_.u_max, m);
    } else if (state_ == proto::RunState::Neutral) {
      neutral(u_);
    }
    hal_.actuate(u_, m);
    if (driving) {
      stats_.add(hal_.ticks() - t0);
      if (step_ % ident_.decimation() == 0) send_ident_sample(l);
      ++step_;
      if (ident_.done()) {
        state_ = proto::RunState::Idle;
        ident_.end();
        watchdog_ = 0;
        neutral(u_);
        hal_.actuate(u_, m);
        log(proto::LogLevel::Info, "identification run finished: its duration is over, actuators neutral");
      }
    }
    tx_.drain(hal_);
  }

  void send_ident_sample(const float* l) {
    proto::IdentSample t;
    t.tseq = tseq_++;
    t.m = rig_.m;
    t.n = have_y_true_ ? rig_.n : 0;
    t.w = rig_.w;
    t.step = step_;
    t.time_us = clock_.us();
    for (int i = 0; i < rig_.m; ++i) t.u[i] = u_[i];
    for (int j = 0; j < t.n; ++j) t.y[j] = y_true_[j];
    for (int j = 0; j < rig_.w; ++j) t.l[j] = l[j];
    uint8_t wire[proto::kWireBufferSize];
    const size_t len = proto::encode(t, unsolicited_seq_++, 0, wire, sizeof wire);
    send_sample(wire, len);
  }

  // A sample frame (TELEMETRY or IDENT_SAMPLE), with its step's
  // SENSOR_SAMPLE before it while the stream is on (closed loop only) and,
  // on a rig with chips, its SENSOR_HEALTH right behind it: queued together
  // or dropped together, counted once in tx_dropped (PROTOCOL.md 9.6), so a
  // console never gets the one without the others.
  void send_sample(const uint8_t* wire, size_t len, const uint8_t* before = nullptr, size_t before_len = 0) {
    uint8_t health[32];  // SENSOR_HEALTH is 19 bytes on the wire
    const size_t health_len = len == 0 ? 0 : encode_health(health, sizeof health);
    const uint8_t* frames[3] = {before, wire, health};
    const size_t lens[3] = {before_len, len, health_len};
    if (len == 0 || !tx_.push_group(frames, lens, 3)) ++tx_dropped_;
  }

  void ident_start(uint8_t type, const proto::IdentStart& p) {
    if (state_ != proto::RunState::Idle) {
      if (ident_.active() && p.run_id == run_id_) return ack(type);  // a retry
      return nack(type, proto::StatusCode::WrongState, 0, proto::kNoField);
    }
    const IdentRefusal r = ident_.start(p, float(id_.loop_rate_hz), params_.u_min, params_.u_max, rig_);
    if (r.status != proto::StatusCode::Ok) return nack(type, r.status, r.field, proto::kNoField);
    run_id_ = p.run_id;
    step_ = 0;
    stats_.reset();
    hal_.run_begins();
    watchdog_ = settings_.watchdog_ms ? watchdog_bits::kArmed : 0;
    link_back_reported_ = false;
    last_rx_ms_ = clock_.ms();
    state_ = proto::RunState::Ident;
    ack(type);
  }

  // ------------------------------------------------------------- requests
  void handle(const proto::FrameView& f) {
    const uint32_t heard_before_ms = last_rx_ms_;
    last_rx_ms_ = clock_.ms();
    if (watchdog_ & watchdog_bits::kTripped && !link_back_reported_) {
      const uint32_t silent_ms = last_rx_ms_ - heard_before_ms;
      link_back_reported_ = true;
      // How long, by this firmware's clock: set beside the console's own
      // gap between writes, it tells a silent console from a line (or a
      // host) that held its bytes back.
      LogText<proto::kMaxLogText> text;
      text << "link back after " << silent_ms << " ms of silence during the run (watchdog_ms "
           << uint32_t(settings_.watchdog_ms)
           << "), actuators went to the safe state; RUN_HOLD resume continues";
      log(proto::LogLevel::Warn, text.c_str());
    }
    if (f.is_reply()) return;  // not a request
    const uint8_t* wire;
    size_t size;
    if (cache_.find(f, wire, size)) {
      tx_.push(wire, size, false);
      return;
    }
    reply_seq_ = f.header.seq;
    request_ = f;
    replied_ = false;
    dispatch(f);
    if (!replied_) nack(f.header.type, proto::StatusCode::Unsupported, proto::kNoField, proto::kNoField);
  }

  template <class M>
  bool unpack_or_nack(const proto::FrameView& f, M& m) {
    if (proto::unpack(f, m) == proto::StatusCode::Ok) return true;
    nack(f.header.type, proto::StatusCode::BadLength, proto::kNoField, proto::kNoField);
    return false;
  }

  void dispatch(const proto::FrameView& f) {
    using T = proto::MsgType;
    switch (T(f.header.type)) {
      case T::Ping: {
        proto::Ping p;
        if (!unpack_or_nack(f, p)) return;
        proto::Pong r;
        r.nonce = p.nonce;
        r.uptime_ms = clock_.ms();
        return reply(r);
      }
      case T::InfoGet: return reply(info());  // INFO_EX: a 1.1 console reads both
      case T::RigGet: return reply(rig_info_now());
      case T::ParamList: {
        proto::ParamList p;
        if (!unpack_or_nack(f, p)) return;
        proto::ParamDesc d;
        if (!params_svc_.describe(p.index, d)) return nack(f.header.type, proto::StatusCode::UnknownId, 0, proto::kNoField);
        return reply(d);
      }
      case T::ParamGet: {
        proto::ParamGet p;
        if (!unpack_or_nack(f, p)) return;
        return param_reply(f.header.type, params_svc_.get(p.id));
      }
      case T::ParamSet: {
        proto::ParamSet p;
        if (!unpack_or_nack(f, p)) return;
        const ParamReply r = params_svc_.set(p);
        if (r.status == proto::StatusCode::Ok) model_.reconfigure();
        return param_reply(f.header.type, r);
      }
      case T::RefSelect: {
        proto::RefSelect p;
        if (!unpack_or_nack(f, p)) return;
        const RefRefusal r = ref_.select(p);
        return r.status == proto::StatusCode::Ok ? ack(f.header.type) : nack(f.header.type, r.status, r.field, r.element);
      }
      case T::XferBegin: {
        proto::XferBegin p;
        if (!unpack_or_nack(f, p)) return;
        proto::TransferReceiver* rx = receiver(p.kind);
        if (!rx) return nack(f.header.type, no_receiver(p.kind), 0, proto::kNoField);
        if (rx == &model_rx_ && state_ != proto::RunState::Idle && model_.in_staging())
          return nack(f.header.type, proto::StatusCode::WrongState, proto::kNoField, proto::kNoField);
        // After the size rules of TransferReceiver::begin (out_of_range, too_large): section 9.4's order.
        if (rx == &model_rx_ && p.total_size != 0 && p.total_size <= rx->capacity() &&
            model_size_refused(rig_info_now(), p))
          return nack(f.header.type, proto::StatusCode::Unsupported, 2, proto::kNoField);
        const proto::XferReply r = rx->begin(p);
        // Only an accepted BEGIN may touch the model in force: a NACK changes nothing.
        if (rx == &model_rx_ && r.status == proto::StatusCode::Ok) model_.restore_builtin();
        return xfer_reply(f.header.type, r);
      }
      case T::XferChunk: {
        proto::XferChunk p;
        if (!unpack_or_nack(f, p)) return;
        proto::TransferReceiver* rx = receiver(p.kind);
        if (!rx) return nack(f.header.type, no_receiver(p.kind), 0, proto::kNoField);
        const uint32_t before = rx->next_offset();
        const proto::XferReply r = rx->chunk(p);
        if (rx == &model_rx_ && r.status == proto::StatusCode::Ok) {
          const proto::StatusCode v = model_header_verdict(rig_info_now(), *rx, before);
          if (v != proto::StatusCode::Ok) {
            rx->close();  // the model in force stays (the built-in one since BEGIN)
            log(proto::LogLevel::Warn, "model upload refused at its header: a shape RIG_INFO does not accept");
            return nack(f.header.type, v, 2, proto::kNoField);
          }
        }
        return xfer_reply(f.header.type, r);
      }
      case T::XferCommit: {
        proto::XferCommit p;
        if (!unpack_or_nack(f, p)) return;
        return commit(f.header.type, p.kind);
      }
      case T::XferAbort: {
        proto::XferAbort p;
        if (!unpack_or_nack(f, p)) return;
        if (proto::TransferReceiver* rx = receiver(p.kind)) rx->close();
        return ack(f.header.type);
      }
      case T::RunStart: {
        proto::RunStart p;
        if (!unpack_or_nack(f, p)) return;
        return run_start(f.header.type, p.run_id);
      }
      case T::IdentStart: {
        if constexpr ((Features & feature::kIdent) != 0) {
          if (!offers(feature::kIdent)) return;  // unsupported (handle())
          proto::IdentStart p;
          if (!unpack_or_nack(f, p)) return;
          ident_start(f.header.type, p);
        }
        return;
      }
      case T::RunStop:
        state_ = proto::RunState::Idle;
        ident_.end();
        watchdog_ = 0;
        return ack(f.header.type);
      case T::RunHold: {
        proto::RunHold p;
        if (!unpack_or_nack(f, p)) return;
        return run_hold(f.header.type, p.mode);
      }
      case T::TelemetryConfig: {
        proto::TelemetryConfig p;
        if (!unpack_or_nack(f, p)) return;
        if (p.mask & proto::telemetry_field::kYTrue && !id_.has_y_true)
          return nack(f.header.type, proto::StatusCode::Unsupported, 0, proto::kNoField);
        mask_ = p.mask;
        decimation_ = p.decimation;
        return ack(f.header.type);
      }
      case T::SensorStream: {
        proto::SensorStream p;
        if (!unpack_or_nack(f, p)) return;
        // A rig without sensors has nothing to stream: no capability bit.
        if (rig_.w == 0) return nack(f.header.type, proto::StatusCode::Unsupported, proto::kNoField, proto::kNoField);
        if (p.on > 1) return nack(f.header.type, proto::StatusCode::OutOfRange, 0, proto::kNoField);
        sensor_stream_ = p.on != 0;
        return ack(f.header.type);
      }
      case T::StatusGet: return send_status(f.header.seq, true);
      case T::DeviceGet: {
        proto::DeviceGet p;
        if (!unpack_or_nack(f, p)) return;
        proto::DeviceStatus d;
        if (!device_status(p.index, d)) return nack(f.header.type, proto::StatusCode::UnknownId, 0, proto::kNoField);
        return reply(d);
      }
      case T::Settings: {
        proto::Settings p;
        if (!unpack_or_nack(f, p)) return;
        return settings(f.header.type, p.action);
      }
      default: return;  // handle() answers Unsupported
    }
  }

  void run_start(uint8_t type, uint32_t run_id) {
    const bool active = state_ != proto::RunState::Idle;
    // A retry only of a closed-loop run: the identification run's own id
    // is refused as IDENT_START refuses a closed-loop run's (9.5).
    if (active && !ident_.active() && run_id == run_id_) return ack(type);
    if (active) return nack(type, proto::StatusCode::WrongState, 0, proto::kNoField);
    if (!model_.has()) return nack(type, proto::StatusCode::WrongState, proto::kNoField, proto::kNoField);
    run_id_ = run_id;
    step_ = 0;
    stats_.reset();
    hal_.run_begins();
    ident_.end();
    ref_.restart();
    watchdog_ = settings_.watchdog_ms ? watchdog_bits::kArmed : 0;
    link_back_reported_ = false;
    last_rx_ms_ = clock_.ms();
    neutral(u_);
    float l[Cap::w + 1] = {};
    read_sensors(l);
    if (params_.feedback == Feedback::Measured && id_.has_y_true && hal_.read_output(y_true_, rig_.n))
      model_.controller().reset(u_, y_true_, l);
    else
      model_.controller().reset_at_rest(u_, l);
    aimed_ = false;
    state_ = proto::RunState::Running;
    ack(type);
  }

  void run_hold(uint8_t type, uint8_t mode) {
    if (state_ == proto::RunState::Idle) return nack(type, proto::StatusCode::WrongState, 0, proto::kNoField);
    switch (proto::HoldMode(mode)) {
      case proto::HoldMode::Hold: state_ = proto::RunState::Hold; break;
      case proto::HoldMode::Neutral: state_ = proto::RunState::Neutral; break;
      case proto::HoldMode::Resume: {
        if (ident_.active()) {  // the signal continues where it paused
          watchdog_ &= uint8_t(~watchdog_bits::kTripped);
          link_back_reported_ = false;
          state_ = proto::RunState::Ident;
          break;
        }
        if (state_ != proto::RunState::Running) {
          float l[Cap::w + 1] = {};
          read_sensors(l);
          model_.controller().reset_at_rest(u_, l);  // histories restart from where the actuators are
          aimed_ = false;
          watchdog_ &= uint8_t(~watchdog_bits::kTripped);
          link_back_reported_ = false;
        }
        state_ = proto::RunState::Running;
        break;
      }
      default: return nack(type, proto::StatusCode::OutOfRange, 0, proto::kNoField);
    }
    ack(type);
  }

  void commit(uint8_t type, uint8_t kind) {
    proto::TransferReceiver* rx = receiver(kind);
    if (!rx) return nack(type, no_receiver(kind), 0, proto::kNoField);
    const proto::XferReply c = rx->commit();
    if (c.status != proto::StatusCode::Ok) return nack(type, c.status, c.field, proto::kNoField);
    proto::StatusCode s;
    if (kind == uint8_t(proto::XferKind::Model)) {
      if (state_ != proto::RunState::Idle) return nack(type, proto::StatusCode::WrongState, proto::kNoField, proto::kNoField);
      s = model_.commit(rx->data(), rx->size());
    } else {
      s = ref_.commit_table(rx->data(), rx->size(), rig_.n);
    }
    rx->close();
    if (s != proto::StatusCode::Ok) {
      log(proto::LogLevel::Warn, kind == uint8_t(proto::XferKind::Model) ? "model upload refused; the built-in model stays in force" : "reference table refused; the previous table stays");
      return nack(type, s, proto::kNoField, proto::kNoField);
    }
    ack(type);
  }

  // SETTINGS (PROTOCOL.md 9.11). Save and defaults only while idle: a
  // sector erase stalls a board's CPU (its code runs from the same flash).
  void settings(uint8_t type, uint8_t action) {
    if constexpr (!Settings) {
      (void)action;
      return nack(type, proto::StatusCode::Unsupported, proto::kNoField, proto::kNoField);
    } else {
      settings_request(type, action);
    }
  }
  void settings_request(uint8_t type, uint8_t action) {
    using A = proto::SettingsAction;
    if (!settings_svc_.attached()) return nack(type, proto::StatusCode::Unsupported, proto::kNoField, proto::kNoField);
    if (action > uint8_t(A::Report)) return nack(type, proto::StatusCode::OutOfRange, 0, proto::kNoField);
    if (action != uint8_t(A::Report) && state_ != proto::RunState::Idle)
      return nack(type, proto::StatusCode::WrongState, 0, proto::kNoField);
    proto::StatusCode s = proto::StatusCode::Ok;
    if (action == uint8_t(A::Save)) s = settings_svc_.save();
    if (action == uint8_t(A::Defaults)) {
      s = settings_svc_.restore_defaults();
      if (s == proto::StatusCode::Ok) {
        rig_params(rig_, params_);  // the values begin() put in force
        settings_ = FwSettings{};
        model_.reconfigure();
      }
    }
    if (s != proto::StatusCode::Ok) {
      log(proto::LogLevel::Error, s == proto::StatusCode::TooLarge
                                      ? "settings not saved: the parameters do not fit the settings sector"
                                      : "settings not saved: the flash refused (erase, program or read-back); the "
                                        "previous settings stand");
      return nack(type, s, proto::kNoField, proto::kNoField);
    }
    ack(type);
    settings_svc_.log_again();
    settings_log();
  }

  // The LOG of where the settings in force came from; pending until the
  // TX queue has room for it.
  void settings_log() {
    LogText<proto::kMaxLogText> text;
    settings_svc_.describe(text);
    if (queue_log(settings_svc_.log_level(), text.c_str())) settings_svc_.log_sent();
  }

  // The receiver of a kind this image takes; null for an unknown kind, and
  // for one it was built without (or whose rig leaves it out).
  proto::TransferReceiver* receiver(uint8_t kind) {
    if (kind == uint8_t(proto::XferKind::Model) && offers(feature::kModelUpload)) return &model_rx_;
    if (kind == uint8_t(proto::XferKind::RefTable) && offers(feature::kTableUpload)) return &table_rx_;
    return nullptr;
  }
  // What XFER answers for a kind without a receiver (PROTOCOL.md 9.4):
  // unknown_id for a kind the protocol does not have, unsupported for one
  // this image leaves out.
  static proto::StatusCode no_receiver(uint8_t kind) {
    return kind == uint8_t(proto::XferKind::Model) || kind == uint8_t(proto::XferKind::RefTable)
               ? proto::StatusCode::Unsupported
               : proto::StatusCode::UnknownId;
  }

  // The image has the service and its rig asks for it.
  bool offers(uint32_t f) const { return (Features & f) != 0 && (rig_.features & f) != 0; }

  // ----------------------------------------------------------- replies
  template <class M>
  void reply(const M& msg) {
    uint8_t wire[proto::kWireBufferSize];
    const size_t len = proto::encode_reply(msg, reply_seq_, wire, sizeof wire);
    if (len == 0) return;
    tx_.push(wire, len, false);
    cache_.store(request_, wire, len);
    replied_ = true;
  }
  void ack(uint8_t type) {
    proto::Ack a;
    a.request_type = type;
    reply(a);
  }
  void nack(uint8_t type, proto::StatusCode s, uint8_t field, uint8_t element) {
    proto::Nack n;
    n.request_type = type;
    n.status = uint8_t(s);
    n.field = field;
    n.element = element;
    reply(n);
  }
  void param_reply(uint8_t type, const ParamReply& r) {
    if (r.status != proto::StatusCode::Ok) return nack(type, r.status, r.field, r.element);
    reply(r.value);
  }
  void xfer_reply(uint8_t type, const proto::XferReply& r) {
    if (r.status != proto::StatusCode::Ok) return nack(type, r.status, r.field, proto::kNoField);
    reply(r.ack);
  }

  proto::InfoEx info() const {
    proto::InfoEx x;
    x.table_max = offers(feature::kTableUpload) ? uint32_t(table_rx_.capacity()) : 0;
    x.model_max = offers(feature::kModelUpload) ? uint32_t(model_rx_.capacity()) : 0;
    proto::Info& i = x.info;
    i.platform = uint8_t(rig_.platform);
    i.m = rig_.m, i.n = rig_.n, i.w = rig_.w, i.nd = rig_.nd, i.dd = rig_.dd;
    i.max_n = uint8_t(Cap::N > 255 ? 255 : Cap::N);
    i.max_nc = uint8_t(Cap::Nc);
    i.fw_major = id_.major, i.fw_minor = id_.minor, i.fw_patch = id_.patch;
    i.loop_rate_hz = id_.loop_rate_hz;
    i.model_hash = model_.hash();
    i.param_hash = param_hash_;
    namespace c = proto::capability;
    i.capabilities = c::kParams | c::kRefBuiltin | c::kTelemetry | c::kRunHold | c::kLog | c::kRig | c::kDevices |
                     (id_.has_y_true ? c::kYTrue : 0) | (rig_.w > 0 ? c::kSensorStream : 0);
    // The services it may leave out (PROTOCOL.md 9.12); saved settings only
    // with a store that answers. Their bits taken at compile time: the
    // table's names stay out of the image.
    constexpr uint32_t ident = firmware_feature(feature::kIdent)->capabilities,
                       model = firmware_feature(feature::kModelUpload)->capabilities,
                       table = firmware_feature(feature::kTableUpload)->capabilities,
                       saved = firmware_feature(feature::kSettings)->capabilities;
    i.capabilities |= (offers(feature::kIdent) ? ident : 0) | (offers(feature::kModelUpload) ? model : 0) |
                      (offers(feature::kTableUpload) ? table : 0) | (settings_attached() ? saved : 0);
    std::strncpy(i.firmware, id_.name, proto::kMaxNameLen);
    return x;
  }

  void send_status(uint8_t seq, bool as_reply) {
    proto::Status s;
    s.uptime_ms = clock_.ms();
    s.run_id = run_id_;
    s.step = step_;
    s.run_state = uint8_t(state_);
    s.watchdog = watchdog_;
    s.telemetry_mask = mask_;
    s.ref_id = ref_.id();
    const proto::DecoderStats& d = decoder_.stats();
    s.frames_in = d.frames_ok;
    s.crc_errors = d.error_count(proto::FrameError::BadCrc);
    s.frame_errors = d.error_total() - s.crc_errors;
    s.tx_dropped = tx_dropped_;
    s.loop_overruns = overruns_;
    s.compute_min = stats_.count ? stats_.min : 0;
    s.compute_mean = stats_.mean();
    s.compute_max = stats_.max;
    s.tick_rate_hz = hal_.tick_rate_hz();
    if (as_reply) return reply(s);
    uint8_t wire[proto::kWireBufferSize];
    const size_t len = proto::encode(s, unsolicited_seq_++, 0, wire, sizeof wire);
    if (!tx_.push(wire, len, false)) ++tx_dropped_;
    (void)seq;
  }

  // What this step aimed the next one's output at, and predicted of it.
  void aim(const float* ref, const StepResult<Cap>& r) {
    for (int j = 0; j < rig_.n; ++j) y_ref_[j] = ref[j], y_predicted_[j] = r.y_hat[j];
    aimed_ = true;
  }

  void send_telemetry(const StepResult<Cap>& r, uint32_t compute) {
    proto::Telemetry t;
    t.tseq = tseq_++;
    t.mask = mask_;
    t.n = uint8_t(rig_.n);
    t.m = uint8_t(rig_.m);
    t.step = step_;
    t.time_us = clock_.us();
    for (int j = 0; j < rig_.n; ++j) {
      t.y_ref[j] = y_ref_[j];
      t.y_hat[j] = y_predicted_[j];
      t.y_true[j] = y_true_[j];
    }
    for (int i = 0; i < rig_.m; ++i) t.u[i] = r.u[i];
    t.cost = r.cost;
    t.iterations = r.iterations;
    t.compute_ticks = compute;
    uint8_t wire[proto::kWireBufferSize];
    const size_t len = proto::encode(t, unsolicited_seq_++, 0, wire, sizeof wire);
    // The sensors the step read, what a model learns from (PROTOCOL.md 9.6).
    uint8_t sensors[proto::kMaxSensorChannels * 4 + 4 + 9];  // payload, header, CRC, COBS, delimiter
    size_t sensors_len = 0;
    if (sensor_stream_) {
      proto::SensorSample ss;
      ss.step = step_;
      ss.w = uint8_t(rig_.w);
      for (int j = 0; j < rig_.w; ++j) ss.l[j] = l_[j];
      sensors_len = proto::encode(ss, unsolicited_seq_++, 0, sensors, sizeof sensors);
    }
    send_sample(wire, len, sensors, sensors_len);
  }

  // For each sample frame of an image with sensor chips: which channels of
  // that step are invalid, and how old its chip samples are. The frame's
  // length, 0 without chips.
  size_t encode_health(uint8_t* wire, size_t cap) {
    if (!chips() || sensors_->count() == 0) return 0;
    proto::SensorHealth h;
    h.step = step_;
    h.invalid = health_.invalid;
    // 65535: no chip channel valid; a valid sample's age saturates below it.
    h.age_ms = health_.age_ms == SensorHealth::kNoValidSample ? 0xFFFFu
               : uint16_t(health_.age_ms > 0xFFFEu ? 0xFFFEu : health_.age_ms);
    return proto::encode(h, unsolicited_seq_++, 0, wire, cap);
  }

  // DEVICE_GET's answer for device `index`; false past the last.
  bool device_status(uint8_t index, proto::DeviceStatus& d) const {
    const int count = chips() ? sensors_->count() : 0;
    if (index >= count) return false;
    const RigDeviceConfig& c = sensors_->device(index);
    d.index = index;
    d.count = uint8_t(count);
    d.state = uint8_t(sensors_->state(index));
    d.bus = c.bus;
    d.address = c.kind == BusKind::Spi ? c.cs : c.address;  // a servo's id on a serial bus
    d.age_ms = sensors_->age_ms(index, clock_.ms());
    d.faults = sensors_->faults(index);
    std::strncpy(d.name, c.name, proto::kMaxNameLen);
    return true;
  }

  void log(proto::LogLevel level, const char* text) {
    if (!queue_log(level, text)) ++tx_dropped_;
  }

  // A LOG into the TX queue if it has room (leaving the reserve for
  // replies); false, and nothing sent or counted, if not.
  bool queue_log(proto::LogLevel level, const char* text) {
    proto::Log g;
    g.level = uint8_t(level);
    // A bounded copy, always terminated (strncpy's truncation warning fires
    // on callers whose buffers are exactly the text's length).
    size_t i = 0;
    for (; i < proto::kMaxLogText && text[i] != '\0'; ++i) g.text[i] = text[i];
    g.text[i] = '\0';
    uint8_t wire[proto::kWireBufferSize];
    const size_t len = proto::encode(g, unsolicited_seq_, 0, wire, sizeof wire);
    if (len == 0 || !tx_.push(wire, len, true)) return false;
    ++unsolicited_seq_;
    return true;
  }

  // ------------------------------------------------------------ sensors
  // The port's channels, then the chips' latest samples over theirs: the
  // step never waits on a bus.
  void read_sensors(float* l) {
    hal_.read_sensors(l, rig_.w);
    health_ = chips() ? sensors_->fill(l, clock_.ms()) : SensorHealth{};
  }

  // Each device's change of state, once (LOG), never dropped: a change
  // whose LOG finds the TX queue full stays pending in the sampler and is
  // sent at a later poll, once the port has taken bytes (at boot a board
  // with six absent chips has more LOGs than a 512-byte queue holds). A
  // chip that changes again meanwhile is logged once, in its state then.
  void report_devices() {
    for (int d; (d = sensors_->peek_change()) >= 0;) {
      const DeviceState st = sensors_->state(d);
      const RigDeviceConfig& c = sensors_->device(d);
      LogText<proto::kMaxLogText> text;
      text << "device " << c.name << " (" << c.chip->name << "): " << proto::device_state_name(uint8_t(st));
      if (st == DeviceState::Fault) {
        const char* names[4];
        const size_t n = sensors_->fault_names(d, names, 4);
        for (size_t i = 0; i < n; ++i) text << (i == 0 ? ": " : ", ") << names[i];
      }
      if (c.kind == BusKind::Serial && st == DeviceState::Fault)
        text << (c.release_on_fault ? "; released (torque off)" : "; held at its last goal");
      if (st == DeviceState::Fault)
        text << "; its channels are invalid until it answers without an error";
      else if (st != DeviceState::Ok)
        text << "; its sensor channels are invalid until it answers again";
      if (!queue_log(st == DeviceState::Ok ? proto::LogLevel::Info : proto::LogLevel::Warn, text.c_str())) return;
      sensors_->take_change();
    }
  }

  // ---------------------------------------------------------- watchdog
  void watchdog_check() {
    if (!(watchdog_ & watchdog_bits::kArmed) ||
        (state_ != proto::RunState::Running && state_ != proto::RunState::Ident))
      return;
    if (settings_.watchdog_ms == 0 || clock_.ms() - last_rx_ms_ <= settings_.watchdog_ms) return;
    state_ = settings_.safe_state == 0 ? proto::RunState::Hold : proto::RunState::Neutral;
    watchdog_ |= watchdog_bits::kTripped;
    link_back_reported_ = false;
  }

  void neutral(float* u) const {
    // The rig's neutral input, inside the limits in force (a tuned u_min or
    // u_max may have moved past it).
    for (int i = 0; i < rig_.m; ++i) {
      const float v = rig_.u_neutral[i];
      u[i] = v < params_.u_min[i] ? params_.u_min[i] : (v > params_.u_max[i] ? params_.u_max[i] : v);
    }
  }

  Hal& hal_;
  Identity id_;
  const RigConfig& rig_;
  Params<Cap> params_{};
  FwSettings settings_{};
  ParamService<Cap> params_svc_;
  // Empty without Settings, so an image without a store pays no RAM either.
  std::conditional_t<Settings, SettingsService<Cap>, NoSettingsService> settings_svc_{params_svc_};
  bool settings_attached() const {
    if constexpr (Settings) return settings_svc_.attached();
    return false;
  }
  ReferenceSlot ref_;
  ModelSlot<Cap> model_;
  proto::TransferReceiver model_rx_, table_rx_;

  proto::Decoder decoder_{};
  TxQueue<TxCapacity> tx_{};
  proto::ReplyCache cache_{};
  proto::FrameView request_{};  // the request being answered (valid during dispatch)
  uint8_t reply_seq_ = 0;
  bool replied_ = false;
  uint8_t unsolicited_seq_ = 0;
  uint32_t param_hash_ = 0;  // the list never changes at run time: hashed once
  uint16_t tseq_ = 0;

  Clock clock_{};
  uint32_t last_heartbeat_ms_ = 0, last_rx_ms_ = 0;
  proto::RunState state_ = proto::RunState::Idle;
  uint32_t run_id_ = 0, step_ = 0;
  uint8_t mask_ = proto::telemetry_field::kAll, watchdog_ = 0;
  bool link_back_reported_ = false;
  uint16_t decimation_ = 1;
  uint32_t overruns_ = 0, tx_dropped_ = 0;
  ComputeStats stats_{};
  float u_[Cap::m] = {}, y_true_[Cap::n] = {};
  // The last closed-loop step's aim r(k+1) and prediction y_hat(k+1), sent
  // with the output measured at k+1; aimed_ is false until a step set them.
  float y_ref_[Cap::n] = {}, y_predicted_[Cap::n] = {};
  bool aimed_ = false;
  float l_[Cap::w + 1] = {};  // the sensors of the step (+1: msd has none)
  bool sensor_stream_ = false;  // SENSOR_SAMPLE before each TELEMETRY (SENSOR_STREAM)
  bool have_y_true_ = false;
  // Constant false without Chips, so the compiler drops every use.
  bool chips() const {
    if constexpr (Chips) return sensors_ != nullptr;
    return false;
  }
  SensorSampler* sensors_ = nullptr;
  SensorHealth health_{};  // of l_: the chip channels invalid at this step, the oldest sample's age
  std::conditional_t<(Features & feature::kIdent) != 0, IdentRun, NoIdentRun> ident_{};
  bool shape_list_ = false;
};

}  // namespace nlsoft::fw
