#pragma once
// What `ident` asks the firmware for (protocol 1.3, IDENT_START), from the
// command's words and the firmware's rate and dimensions: the signal, its
// band, amplitude and seed, the duration in control steps, and the
// decimation the line carries. Shared by the `ident` command and the
// script's `ident` line, so both accept and refuse the same words.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "protocol/messages.hpp"

namespace nlsoft::host {
struct Rig;
}  // namespace nlsoft::host

namespace nlsoft::console {

// The signals by IDENT_START's numbering (protocol::IdentSignal), named as
// shared/excitation.hpp names them, and the words that list them for an
// error or --help ("steps, prbs, ... or aprbs").
extern const std::vector<std::string> kIdentSignals;
std::string ident_signal_list();

struct IdentWords {
  std::string signal = "aprbs";  // one of kIdentSignals
  std::string duration;         // 10min, 60s, ...
  std::string band;             // LO:HI in Hz; empty: the rig file's [ident], else 0.05:2
  uint32_t seed = 1;
  std::optional<double> amplitude;  // unset: the rig file's [ident], else 0.8
  bool joint = false;
  bool mixed = false;  // a shared deviation plus each input's own (IDENT_MIXED)
  int decimation = 0;  // 0: every step on a simulator, else what the baud rate carries
};

// The words alone (before anything is started): throws CliError naming the
// bad one. Returns the duration in seconds.
double check_ident_words(const IdentWords& w);

struct IdentLine {
  unsigned baud = 115200;
  bool unlimited = false;  // a simulator or a pty: every step fits
  // Each sample is followed by a SENSOR_HEALTH (a board image whose rig
  // reads sensor chips, PROTOCOL.md 7): 19 more bytes a sample on the wire.
  bool sensor_health = false;
};

struct IdentPlan {
  protocol::IdentStart start;  // run_id filled in when the run starts
  std::string excitation_json;
  std::string excitation_words;  // the signal, its band and amplitude and where each came from, for the user
  std::string line_words;        // what the line carries, for the user
  double seconds = 0;
};

// Against the firmware's rate (Hz) and m, n, w: throws CliError for a band
// past half the rate or a duration under one step. The band and amplitude
// the words leave out come from `rig`'s [ident] (nullptr: no rig file
// known), else ident's own defaults; excitation_words says which.
IdentPlan plan_ident(const IdentWords& w, double rate_hz, int m, int n, int w_sensors, const IdentLine& line,
                     const host::Rig* rig);

// Throws CliError when the firmware (its INFO and protocol_minor) lacks
// what `start` needs: identification runs (IDENT), or MIXED (IDENT_MIXED),
// which a firmware without it would ignore rather than refuse.
void check_firmware_offers(const protocol::IdentStart& start, const protocol::Info& info, uint8_t protocol_minor);

// IDENT_SAMPLE's size on the wire for these dimensions (with the
// SENSOR_HEALTH that follows it, when it does), and the smallest decimation
// whose samples fit four fifths of an 8N1 line at `baud` (the rest is for
// replies and STATUS, as for TELEMETRY).
size_t ident_sample_wire_bytes(int m, int n, int w, bool sensor_health = false);
uint16_t ident_decimation_for(double rate_hz, int m, int n, int w, unsigned baud, bool sensor_health = false);

// Whether the firmware follows each sample with a SENSOR_HEALTH: it lists
// sensor chips (DEVICE_GET, the DEVICES capability).
class Device;
bool sends_sensor_health(Device& device);

}  // namespace nlsoft::console
