#pragma once
// A rig as data: everything that makes hasel a hasel (dimensions, rate,
// actuator limits, outputs and their task space, sensors and their pins,
// controller defaults, model shape, simulated stand-in, default reference,
// identification defaults),
// read from a TOML rig file (docs/rig-file.md). A plain value: rig_loader.cpp
// alone reads TOML, everything else takes a `const Rig&`.
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "shared/excitation.hpp"
#include "shared/firmware_features.hpp"
#include "shared/layer_kind.hpp"
#include "shared/params.hpp"
#include "shared/plant_registry.hpp"
#include "shared/reference.hpp"
#include "shared/rig_devices.hpp"

namespace nlsoft::host {

// What a rig file may describe. The loader refuses more; the console's
// controller (HostCapacity) holds all of it; each MCU image holds its own
// rig's dimensions only.
struct RigCapacity {
  static constexpr int m = 8, n = 6, w = 32, nd = HostCapacity::nd;
  // The network's input length p = nd m + dd n + w (paper, "Problem Statement").
  static constexpr int p = HostCapacity::inputs;
  // The horizons the console's controller holds (HostCapacity).
  static constexpr int N = HostCapacity::N, Nc = HostCapacity::Nc;
  // Sensor chips on the board's buses ([[device]]).
  static constexpr int devices = kRigMaxDevices;
};
// A sensor channel's validity is one bit of SENSOR_HEALTH's u32 mask.
static_assert(RigCapacity::w <= 32, "more sensor channels than SENSOR_HEALTH's mask holds");

// A bad rig file: the message starts with "file:line: " and names the key.
struct RigError : std::runtime_error {
  RigError(const std::string& message, std::string in_file, int at_line, std::string at_key)
      : std::runtime_error(message), file(std::move(in_file)), line(at_line), key(std::move(at_key)) {}
  std::string file;
  int line;
  std::string key;
};

struct RigInput {
  std::string name, unit;
  double min = 0, max = 0, neutral = 0;
  std::string pwm;  // the board's PWM pin ("PC6"); empty when not wired
  int line = 0, pwm_line = 0;  // of the [[input]] table and its pwm key, for errors about the board
  // A servo drives it instead ([[device]] on a serial bus, by name): its
  // goal position = goal_at_neutral + goal_per_unit * (u - neutral), in the
  // servo's goal steps.
  std::string servo;
  int servo_device = -1;  // its row of Rig::devices
  double goal_per_unit = 0, goal_at_neutral = 0;
  int servo_line = 0;
};

// How an output reaches the console: an ADC channel on the board, an
// external observer (a position sensor on the plant, the simulator), or
// not at all (the controller runs on its own predictions).
enum class OutputSource { None, Adc, External };
// Where a sensor channel is read: an ADC channel on the board, a channel of
// a chip on one of its buses ([[device]]), or nowhere on this board
// (declared so the network input keeps its place; reads 0).
enum class SensorSource { None, Adc, Device };

// A sensor chip on a bus of the board ([[device]]), checked against its
// chip's spec (shared/chips/) and the board's buses (board_pins.hpp).
struct RigDevice {
  std::string name;
  const chips::ChipSpec* chip = nullptr;
  std::string bus;     // the board's bus name ("i2c1")
  int bus_index = 0;   // its row of the board's buses
  BusKind kind = BusKind::I2c;
  int address = 0;     // I²C: 7-bit
  std::string cs;      // SPI: the chip-select pin ("PA8")
  int cs_index = 0;    // its row of the board's chip selects
  uint32_t clock_hz = 0;
  double range = 0;    // in the chip's range_unit; 0 when the chip has no range setting
  uint8_t range_bits = 0;
  double rate_hz = 0;  // 0 when the chip has no rate setting
  uint8_t rate_bits = 0;
  int line = 0;        // of the [[device]] table
  bool release_on_fault = false;  // a servo: on_fault = "release" (torque off), else "hold"
};

struct RigOutput {
  std::string name, unit;
  double min = 0, max = 0;  // where the output can be (the plant's reach)
  double span = 0;          // the task space's extent: tracking errors are relative to it
  double rest = 0;          // the output with every input at neutral: where a trained model is centred
  OutputSource source = OutputSource::None;
  int adc = -1;
  double gain = 1, offset = 0;  // y = offset + gain * volts
  int adc_line = 0;             // of the adc key, for errors about the board
};

struct RigSensor {
  std::string name, unit;
  SensorSource source = SensorSource::None;
  int adc = -1;  // ADC1 channel
  int device = -1, channel = -1;  // source = "device": the rig's device and the chip's channel
  double gain = 1, offset = 0;  // value = offset + gain * volts (a device: * the chip's reading)
  int line = 0, adc_line = 0;  // of the [[sensor]] table and its adc key, for errors about the board
};

// The controller's defaults, as PARAM_SET would hold them.
struct RigController {
  std::vector<double> Q, Lambda;
  double s = 0, b = 0, r = 1, eps = 1e-3, nr_tol = 1e-4;
  int N = 1, N1 = 1, Nc = 1, nr_max_iter = 3;
  DerivMode mode = DerivMode::Exact;
  Feedback feedback = Feedback::Predicted;
};

struct RigLayer {
  LayerKind kind = LayerKind::Dense;  // the file's kind = "dense" | "gru" (shared/layer_kind.hpp)
  int units = 0;
  std::string activation;  // dense: relu, tanh, sigmoid, linear; gru: empty
};

struct RigModel {
  std::string file;  // a shipped model ("hasel.nlsm"); empty: none named
  std::vector<RigLayer> layers;
};

// One actuator of a generic plant ([[plant.actuator]], shared/plant_generic.hpp).
struct RigActuator {
  double gain = 1;
  GenericShape shape = GenericShape::Linear;
  double knee = 1, exponent = 1;  // tanh/saturation; power
  double play = 0, tau = 0;       // hysteresis half-width (input units); lag, s
};

struct RigPlant {
  // The plant registry's row `kind` names (shared/plant_registry.hpp);
  // nullptr: the file has no [plant].
  const PlantEntry* kind = nullptr;
  int line = 0;
  // kind = "generic": every constant of the plant, in the rig's units.
  std::vector<RigActuator> actuators;              // one per [[input]]
  std::vector<std::vector<double>> coupling;       // B: n rows of m
  std::vector<double> output_offset, output_tau;   // n each
  std::vector<std::vector<double>> sensor_map;     // C: w rows of m + n
  std::vector<double> sensor_offset, sensor_noise;  // w each
};

// What `ident` drives when its words do not say (docs/rig-file.md,
// [ident]): an excitation's amplitude and band suit one rig's dynamics and
// task, not every rig's. [ident] holds them for every signal, [ident.SIGNAL]
// for one; unset, ident's own defaults stand.
struct RigIdentChoice {
  double amplitude = 0;              // fraction of each input's range, (0, 1]; 0: unset
  double band_lo = 0, band_hi = 0;   // Hz; 0: unset
  std::string amplitude_from, band_from;  // the table that set it ("[ident.steps]"), for ident's words
};

struct RigIdent {
  RigIdentChoice all;
  std::array<RigIdentChoice, kExcitationSignalCount> signal{};  // by ExcitationSignal
  // A signal's own table over [ident], field by field.
  RigIdentChoice for_signal(ExcitationSignal s) const {
    RigIdentChoice c = all;
    const RigIdentChoice& own = signal[size_t(s)];
    if (own.amplitude > 0) c.amplitude = own.amplitude, c.amplitude_from = own.amplitude_from;
    if (own.band_hi > 0) c.band_lo = own.band_lo, c.band_hi = own.band_hi, c.band_from = own.band_from;
    return c;
  }
};

// The default task and the reference paths' geometry (shared/reference.hpp).
struct RigReference {
  RefKind kind = RefKind::Infinity;
  std::array<double, 3> centre{}, amplitude{}, pringle_amplitude{}, swirl_centre{};
  double swirl_scale = 1;
  std::vector<double> step_levels;
};

// [pid]: the PID baseline's gains (shared/pid.hpp), one loop per axis,
// output i on input i; `simulate --controller pid` and `runs replay
// --controller pid` run it. Left out, the rig has no PID baseline.
struct RigPid {
  bool given = false;
  double kp = 0, ki = 0, kd = 0;
  double output_scale = 1;  // u = output_scale (P + I + D)
  double d_filter_tau = 0;  // s; 0: the derivative unfiltered
  int line = 0;             // of the table
};

struct Rig {
  std::string file;  // as given to load_rig
  uint32_t hash = 0;  // rig_file_hash of the file: which rig an image or a simulator was built from
  std::string name, description;
  // INFO's platform byte for this rig's images: a number protocol/PROTOCOL.md
  // assigns (section "Platform"), given by the shipped rigs' files; any
  // other rig's images send Custom (255) and name themselves in RIG_INFO.
  uint8_t info_platform = 255;
  double rate_hz = 0;
  int nd = 0, dd = 0;
  // nd, dd left out or "auto": train searches them (nd, dd hold the longest
  // history the capacity allows until a model gives its own).
  bool lags_auto = false;
  std::string board;
  std::vector<RigInput> inputs;
  std::vector<RigOutput> outputs;
  std::vector<RigSensor> sensors;
  std::vector<RigDevice> devices;
  RigController controller;
  RigModel model;
  RigPlant plant;
  RigReference reference;
  RigIdent ident;
  RigPid pid;
  // [firmware]: the services an image of this rig carries beyond the
  // minimum (shared/firmware_features.hpp). Without the table, all the
  // board can carry.
  uint32_t firmware_features = kAllFirmwareFeatures;
  int firmware_line = 0;  // of `features`; 0 when the file does not list them
  // [firmware] optimize = "size": the image's controller compiled for flash,
  // not speed (shared/hot_path.hpp), with the generic network kernel.
  bool firmware_size_first = false;

  int m() const { return int(inputs.size()); }
  int n() const { return int(outputs.size()); }
  int w() const { return int(sensors.size()); }
};

// Reads and validates a rig file; throws RigError naming the file, the line
// and the key of the first fault.
Rig load_rig(const std::string& path);
// The same from text; `file` names it in errors.
Rig parse_rig(const std::string& text, const std::string& file);
// How many rig files this process has read with load_rig: a command line
// loads its rig once, at the edge, and passes the Rig down (a test counts).
long rig_files_loaded();

// RIG_INFO's rig_hash (PROTOCOL.md 7): the CRC-32 of `text` without CRs,
// trailing blanks, and lines that are then empty or comments, so layout and
// comment lines do not change a rig.
uint32_t rig_file_hash(const std::string& text);

// Lower-case names as rig files write them.
const char* output_source_name(OutputSource s);
const char* sensor_source_name(SensorSource s);

}  // namespace nlsoft::host
