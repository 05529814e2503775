#include "app/live/ident_plan.hpp"

#include "app/link/device.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "host/files/cli_error.hpp"
#include "host/rig/rig.hpp"
#include "shared/excitation.hpp"
#include "app/text/duration.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::RigIdentChoice;

namespace p = protocol;

namespace {

// The default band: slow enough for a soft actuator's lag to show, fast
// enough to move it several times a minute.
constexpr double kDefaultLoHz = 0.05, kDefaultHiHz = 2.0;
// Room at both ends of each input's range: a rig whose limits are its
// hardware's may not want them driven open loop for minutes.
constexpr double kDefaultAmplitude = 0.8;

int signal_index(const std::string& s) {
  for (size_t i = 0; i < kIdentSignals.size(); ++i)
    if (s == kIdentSignals[i]) return int(i);
  return -1;
}

bool parse_band(const std::string& text, double& lo, double& hi) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos) return false;
  try {
    size_t a = 0, b = 0;
    const std::string ls = text.substr(0, colon), hs = text.substr(colon + 1);
    lo = std::stod(ls, &a);
    hi = std::stod(hs, &b);
    return a == ls.size() && b == hs.size() && std::isfinite(lo) && std::isfinite(hi);
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

const std::vector<std::string> kIdentSignals(std::begin(kExcitationSignalNames), std::end(kExcitationSignalNames));

std::string ident_signal_list() {
  std::string s;
  for (size_t i = 0; i < kIdentSignals.size(); ++i)
    s += (i == 0 ? "" : i + 1 == kIdentSignals.size() ? " or " : ", ") + kIdentSignals[i];
  return s;
}

double check_ident_words(const IdentWords& w) {
  if (signal_index(w.signal) < 0)
    throw CliError(fmt::format("ident: '{}' is not a signal; use {}", w.signal, ident_signal_list()));
  if (w.joint && w.mixed)
    throw CliError("ident: --joint and --mixed exclude each other (joint gives every input the same deviation, "
                   "mixed a shared one plus each input's own)");
  if (w.mixed && w.signal == "prbs")
    throw CliError("ident: --mixed needs levels inside the range, and prbs has only +-1: its shared part at +-1 "
                   "leaves no room for each input's own (use aprbs)");
  if (w.amplitude && !(*w.amplitude > 0 && *w.amplitude <= 1))
    throw CliError(fmt::format("ident: --amplitude {:g} is outside (0, 1]: it is the fraction of each input's range "
                               "the signal spans",
                               *w.amplitude));
  if (!w.band.empty()) {
    double lo = 0, hi = 0;
    if (!parse_band(w.band, lo, hi))
      throw CliError(fmt::format("ident: --band '{}' is not LO:HI in Hz (e.g. 0.05:2)", w.band));
    if (!(lo > 0)) throw CliError(fmt::format("ident: --band '{}': the lower edge must be > 0 Hz", w.band));
    if (lo > hi) throw CliError(fmt::format("ident: --band '{}': the lower edge is above the upper one", w.band));
  }
  if (w.decimation < 0 || w.decimation > 65535)
    throw CliError(fmt::format("ident: --decimation {} is outside 1..65535", w.decimation));
  if (w.duration.empty()) throw CliError("ident: --duration is required (e.g. --duration 10min)");
  try {
    return text::parse_duration(w.duration);
  } catch (const std::invalid_argument& e) {
    throw CliError(std::string("ident: --duration ") + e.what());
  }
}

void check_firmware_offers(const p::IdentStart& start, const p::Info& info, uint8_t protocol_minor) {
  const std::string fw =
      fmt::format("{} {}.{}.{}, protocol {}.{}", info.firmware, info.fw_major, info.fw_minor, info.fw_patch,
                  p::kProtocolVersion, protocol_minor);
  if (!(info.capabilities & p::capability::kIdent) && protocol_minor < 3)
    throw CliError(fmt::format("the firmware ({}) has no identification runs (the IDENT capability of protocol "
                               "1.3): update it",
                               fw));
  if (const std::string why = firmware_lacks(info, protocol_minor, feature::kIdent); !why.empty())
    throw CliError(why);
  if ((start.options & p::ident_options::kMixed) && !(info.capabilities & p::capability::kIdentMixed))
    throw CliError(fmt::format("the firmware ({}) has no mixed excitation (the IDENT_MIXED capability; it would "
                               "ignore --mixed and drive one independent stream per input): update it, or leave "
                               "out --mixed",
                               fw));
}

size_t ident_sample_wire_bytes(int m, int n, int w, bool sensor_health) {
  // Header 5, CRC 2, COBS 1, delimiter 1 (PROTOCOL.md 2, 7); SENSOR_HEALTH's
  // payload is u32 step, u32 invalid, u16 age_ms.
  constexpr size_t kFraming = 9, kHealth = 4 + 4 + 2 + kFraming;
  return p::ident_sample_payload_size(unsigned(m), unsigned(n), unsigned(w)) + kFraming + (sensor_health ? kHealth : 0);
}

uint16_t ident_decimation_for(double rate_hz, int m, int n, int w, unsigned baud, bool sensor_health) {
  const double per_s = 0.8 * double(baud) / 10.0 / double(ident_sample_wire_bytes(m, n, w, sensor_health));
  const double d = std::ceil(rate_hz / per_s);
  return uint16_t(std::clamp(d, 1.0, 65535.0));
}

bool sends_sensor_health(Device& device) {
  return (device.info().capabilities & p::capability::kDevices) != 0 && !device.devices().empty();
}

IdentPlan plan_ident(const IdentWords& w, double rate_hz, int m, int n, int w_sensors, const IdentLine& line,
                     const Rig* rig) {
  IdentPlan plan;
  plan.seconds = check_ident_words(w);
  // The words first, then the rig file's [ident.SIGNAL] and [ident], then ident's own.
  const RigIdentChoice file = rig ? rig->ident.for_signal(ExcitationSignal(signal_index(w.signal))) : RigIdentChoice{};
  const std::string in_file = rig ? " of " + rig->file : "";
  double lo = kDefaultLoHz, hi = std::min(kDefaultHiHz, rate_hz / 4), amplitude = kDefaultAmplitude;
  std::string band_from = "ident's default", amplitude_from = "ident's default";
  if (!w.band.empty()) {
    parse_band(w.band, lo, hi);
    band_from = "--band";
  } else if (file.band_hi > 0) {
    lo = file.band_lo, hi = file.band_hi, band_from = file.band_from + in_file;
  }
  if (w.amplitude) {
    amplitude = *w.amplitude, amplitude_from = "--amplitude";
  } else if (file.amplitude > 0) {
    amplitude = file.amplitude, amplitude_from = file.amplitude_from + in_file;
  }
  plan.excitation_words = fmt::format("excitation: {}, band {:g}:{:g} Hz ({}), amplitude {:g} ({}), seed {}", w.signal,
                                      lo, hi, band_from, amplitude, amplitude_from, w.seed);
  if (hi > rate_hz / 2)
    throw CliError(fmt::format("ident: {} {:g}:{:g}{} reaches past half the loop rate ({:g} Hz at {:g} Hz): "
                               "nothing above {:g} Hz can be sampled",
                               w.band.empty() ? "the band" : "--band", lo, hi,
                               w.band.empty() ? " (" + band_from + ")" : "", rate_hz / 2, rate_hz, rate_hz / 2));
  if (lo > hi) lo = hi;  // the default's lower edge above a slow rig's upper one
  const double steps = std::round(plan.seconds * rate_hz);
  if (steps < 1)
    throw CliError(fmt::format("ident: --duration {} is shorter than one control step at {:g} Hz", w.duration, rate_hz));
  if (steps > 4e9) throw CliError(fmt::format("ident: --duration {} is over 2^32 control steps", w.duration));
  if (m + n + w_sensors > p::kMaxIdentFloats)
    throw CliError(fmt::format("ident: m + n + w = {} values a step do not fit one IDENT_SAMPLE (at most {})",
                               m + n + w_sensors, p::kMaxIdentFloats));

  const size_t wire = ident_sample_wire_bytes(m, n, w_sensors, line.sensor_health);
  uint16_t dec = uint16_t(w.decimation);
  const uint16_t carried =
      line.unlimited ? 1 : ident_decimation_for(rate_hz, m, n, w_sensors, line.baud, line.sensor_health);
  const char* what = line.sensor_health ? "IDENT_SAMPLE and its SENSOR_HEALTH are" : "IDENT_SAMPLE is";
  if (dec == 0) dec = carried;
  if (line.unlimited)
    plan.line_words = fmt::format("{} {} bytes on the wire; a simulated line carries every step: {} "
                                  "({:.1f} samples/s at {:g} Hz)",
                                  what, wire, dec == 1 ? "every step is recorded" : fmt::format("one step in {} is recorded", dec),
                                  rate_hz / dec, rate_hz);
  else
    plan.line_words = fmt::format(
        "{} {} bytes on the wire; {} baud carries {:.0f} a second (four fifths of the line), so at {:g} "
        "Hz {} ({:.1f} samples/s){}",
        what, wire, line.baud, 0.8 * line.baud / 10.0 / double(wire), rate_hz,
        dec == 1 ? "every step is recorded" : fmt::format("one step in {} is recorded", dec), rate_hz / dec,
        dec < carried ? fmt::format("; --decimation {} asks for more than the line carries (it needs {}): frames "
                                    "will be lost",
                                    dec, carried)
                      : "");

  p::IdentStart& s = plan.start;
  s.signal = uint8_t(signal_index(w.signal));
  s.options = uint8_t((w.joint ? p::ident_options::kJoint : 0) | (w.mixed ? p::ident_options::kMixed : 0));
  s.decimation = dec;
  s.seed = w.seed;
  s.amplitude = float(amplitude);
  s.band_lo = float(lo);
  s.band_hi = float(hi);
  s.duration = uint32_t(steps);

  nlohmann::json j;
  j["signal"] = w.signal;
  j["seed"] = w.seed;
  j["amplitude"] = amplitude;
  j["band_hz"] = {lo, hi};
  j["joint"] = w.joint;
  j["mixed"] = w.mixed;
  j["duration_steps"] = s.duration;
  j["decimation"] = dec;
  plan.excitation_json = j.dump();
  return plan;
}

}  // namespace nlsoft::console
