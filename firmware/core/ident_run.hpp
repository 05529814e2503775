#pragma once
// The identification run's signal (protocol 9.9): IDENT_START's checks, the
// excitation it configures, and each step's u clamped to the limits in
// force. The firmware keeps the run's state (driving, held, neutral) and
// sends the samples.
#include <cstdint>

#include "protocol/messages.hpp"
#include "protocol/status.hpp"
#include "shared/excitation.hpp"
#include "shared/rig_config.hpp"

namespace nlsoft::fw {

namespace proto = nlsoft::protocol;

// IDENT_START's signal byte is ExcitationSignal's numbering.
static_assert(uint8_t(proto::IdentSignal::Steps) == uint8_t(ExcitationSignal::Steps) &&
                  uint8_t(proto::IdentSignal::Prbs) == uint8_t(ExcitationSignal::Prbs) &&
                  uint8_t(proto::IdentSignal::Walk) == uint8_t(ExcitationSignal::Walk) &&
                  uint8_t(proto::IdentSignal::Chirp) == uint8_t(ExcitationSignal::Chirp) &&
                  uint8_t(proto::IdentSignal::Aprbs) == uint8_t(ExcitationSignal::Aprbs) &&
                  uint8_t(proto::IdentSignal::Aprbs) + 1 == kExcitationSignalCount,
              "IDENT_START.signal and ExcitationSignal number the signals alike");

// An IDENT_START refused, as NACK reports it.
struct IdentRefusal {
  proto::StatusCode status = proto::StatusCode::Ok;
  uint8_t field = proto::kNoField;
};

class IdentRun {
 public:
  // Checks IDENT_START's fields in wire order and, when they pass, sets the
  // signal up and marks the run active; a refusal changes nothing.
  IdentRefusal start(const proto::IdentStart& p, float rate_hz, const float* u_min, const float* u_max,
                     const RigConfig& rig) {
    ExcitationSpec spec;
    spec.signal = ExcitationSignal(p.signal);
    spec.joint = (p.options & proto::ident_options::kJoint) != 0;
    spec.mixed = (p.options & proto::ident_options::kMixed) != 0;
    spec.seed = p.seed;
    spec.amplitude = p.amplitude;
    spec.band_lo = p.band_lo;
    spec.band_hi = p.band_hi;
    spec.duration = p.duration;
    // Wire order: the signal and its options (fields 1, 2), then the run's
    // decimation (3), then the rest of the signal's fields.
    const ExcitationCheck head = check_excitation(spec, rate_hz);
    if (head.field == ExcitationField::Signal || head.field == ExcitationField::Options) return refusal(head);
    if (p.decimation == 0) return {proto::StatusCode::OutOfRange, 3};
    const ExcitationCheck c = gen_.configure(spec, rate_hz, u_min, u_max, rig.u_neutral, rig.m);
    if (c.status != Status::Ok) return refusal(c);
    active_ = true;
    decimation_ = p.decimation;
    return {};
  }

  // Set from an accepted IDENT_START until the signal is over or the run
  // stopped; it stays set while the run is held.
  bool active() const { return active_; }
  void end() { active_ = false; }
  uint16_t decimation() const { return decimation_; }

  // The signal's next u, clamped to the limits in force (a tuned u_min or
  // u_max may have narrowed them during the run).
  void next(float* u, const float* u_min, const float* u_max, int m) {
    gen_.next(u);
    for (int i = 0; i < m; ++i) u[i] = u[i] < u_min[i] ? u_min[i] : (u[i] > u_max[i] ? u_max[i] : u[i]);
  }
  bool done() const { return gen_.done(); }

 private:
  static IdentRefusal refusal(const ExcitationCheck& c) {
    return {proto::StatusCode(uint8_t(c.status)), field(c.field)};
  }
  // Field numbers of IDENT_START's table for each refusal of the signal's checks.
  static uint8_t field(ExcitationField f) {
    switch (f) {
      case ExcitationField::Signal: return 1;
      case ExcitationField::Options: return 2;
      case ExcitationField::Amplitude: return 5;
      case ExcitationField::BandLo: return 6;
      case ExcitationField::BandHi: return 7;
      case ExcitationField::Duration: return 8;
      case ExcitationField::None: break;
    }
    return proto::kNoField;
  }

  Excitation gen_{};
  bool active_ = false;
  uint16_t decimation_ = 1;
};

// What Firmware holds in its place when built without identification
// runs: never active, so the closed-loop handling that asks compiles to
// nothing, and no signal generator is constructed at start-up or kept in RAM.
struct NoIdentRun {
  bool active() const { return false; }
  void end() {}
};

}  // namespace nlsoft::fw
