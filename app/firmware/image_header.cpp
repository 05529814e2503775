#include "app/firmware/image_header.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/files/cli_error.hpp"
#include "app/firmware/generated_text.hpp"
#include "app/model/model_section.hpp"
#include "app/model/model_store.hpp"
#include "host/rig/board_pins.hpp"
#include "host/rig/board_table.hpp"
#include "host/rig/firmware_rig.hpp"
#include "host/rig/rig_plant.hpp"
#include "shared/activation.hpp"
#include "shared/board_stm32f4.hpp"
#include "shared/platform_id.hpp"

namespace nlsoft::console {

using host::Board;
using host::BoardPins;
using host::CliError;
using host::OutputSource;
using host::PinTable;
using host::Rig;
using host::RigController;
using host::RigError;
using host::RigInput;
using host::RigLayer;
using host::RigOutput;
using host::RigSensor;
using host::SensorSource;
using host::board_lacks;
using host::board_named;
using host::board_refusal;
using host::find_board;
using host::firmware_rig;
using host::generic_plant_spec;
using host::has_generic_plant;
using host::image_board_names;

namespace {

[[noreturn]] void fail(const Rig& rig, int line, const std::string& key, const std::string& what) {
  throw RigError(fmt::format("{}:{}: {}: {}", rig.file, line, key, what), rig.file, line, key);
}

// A float literal that reads back as the very float the console computes
// (fmt prints the shortest text that round-trips).
std::string flt(float v) {
  if (!std::isfinite(v)) throw CliError(fmt::format("a rig value is not finite ({})", v));
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s + "f";
}

const char* ref_kind_literal(RefKind k) {
  switch (k) {
    case RefKind::Infinity: return "RefKind::Infinity";
    case RefKind::Pringle: return "RefKind::Pringle";
    case RefKind::Diagonal: return "RefKind::Diagonal";
    case RefKind::Swirl: return "RefKind::Swirl";
    case RefKind::Step: return "RefKind::Step";
    case RefKind::Table: return "RefKind::Table";
    default: return "RefKind::Hold";
  }
}

// A Dense layer's activation is compiled into its kernel when the image
// runs only the model it is built with (no model uploads): that one
// activation's code, none of the others' (shared/net_shape.hpp).
std::string layer_type(const RigLayer& l, bool fixed_model) {
  const LayerKindInfo& kind = layer_kind_info(l.kind);
  if (!kind.free_activation) return fmt::format("KindLayer<LayerKind::{}, {}>", kind.enumerator, l.units);
  struct Literal {
    Activation act;
    const char* name;
  };
  static constexpr Literal kLiterals[] = {{Activation::Linear, "Linear"},
                                          {Activation::Relu, "Relu"},
                                          {Activation::Tanh, "Tanh"},
                                          {Activation::Sigmoid, "Sigmoid"},
                                          {Activation::HardSigmoid, "HardSigmoid"}};
  if (fixed_model)
    for (const Literal& a : kLiterals)
      if (l.activation == activation_name(a.act))
        return fmt::format("DenseLayer<{}, int(Activation::{})>", l.units, a.name);
  return fmt::format("DenseLayer<{}>", l.units);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

void write_text_if_changed(const std::string& path, const std::string& text) {
  if (std::filesystem::exists(path) && read_text(path) == text) return;
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out.flush()) throw CliError(fmt::format("cannot write {}", tmp));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw CliError(fmt::format("cannot write {}: {}", path, ec.message()));
}

std::string rig_config_part(const Rig& rig) {
  const RigConfig c = firmware_rig(rig);
  std::string o;
  o += "// The rig the image serves (shared/rig_config.hpp): every value as the console computes it from the file.\n";
  o += "constexpr RigConfig image_rig() {\n  RigConfig c{};\n";
  // INFO's platform byte: the rig file's info_platform, 255 (Custom) without one.
  o += fmt::format("  c.name = {};\n  c.hash = 0x{:08x}u;\n  c.platform = PlatformId({});\n",
                   cpp_string_literal(rig.name), c.hash, unsigned(c.platform));
  o += fmt::format("  c.m = {}, c.n = {}, c.w = {}, c.nd = {}, c.dd = {};\n", c.m, c.n, c.w, c.nd, c.dd);
  o += fmt::format("  c.rate_hz = {};\n", flt(c.rate_hz));
  for (int i = 0; i < c.m; ++i)
    o += fmt::format("  c.u_min[{0}] = {1}, c.u_max[{0}] = {2}, c.u_neutral[{0}] = {3}, c.Lambda[{0}] = {4};  // {5}\n",
                     i, flt(c.u_min[i]), flt(c.u_max[i]), flt(c.u_neutral[i]), flt(c.Lambda[i]),
                     rig.inputs[size_t(i)].name);
  for (int i = 0; i < c.n; ++i)
    o += fmt::format("  c.Q[{}] = {};  // {}\n", i, flt(c.Q[i]), rig.outputs[size_t(i)].name);
  o += fmt::format("  c.s = {}, c.b = {}, c.r = {}, c.eps = {}, c.nr_tol = {};\n", flt(c.s), flt(c.b), flt(c.r),
                   flt(c.eps), flt(c.nr_tol));
  o += fmt::format("  c.N = {}, c.N1 = {}, c.Nc = {}, c.nr_max_iter = {};\n", c.N, c.N1, c.Nc, c.nr_max_iter);
  o += fmt::format("  c.mode = {};\n  c.feedback = {};\n",
                   c.mode == DerivMode::Exact ? "DerivMode::Exact" : "DerivMode::Fd",
                   c.feedback == Feedback::Predicted ? "Feedback::Predicted" : "Feedback::Measured");
  const RefParams& r = c.reference;
  o += fmt::format("  c.reference.kind = {};\n  c.reference.level_count = {};\n  c.reference.hold = {};\n",
                   ref_kind_literal(r.kind), r.level_count, r.hold);
  o += fmt::format("  c.reference.A = {}, c.reference.B = {}, c.reference.C = {};\n", flt(r.A), flt(r.B), flt(r.C));
  o += fmt::format("  c.reference.c[0] = {}, c.reference.c[1] = {}, c.reference.c[2] = {};\n", flt(r.c[0]),
                   flt(r.c[1]), flt(r.c[2]));
  o += fmt::format("  c.reference.omega = {}, c.reference.lambda = {}, c.reference.scale = {};\n", flt(r.omega),
                   flt(r.lambda), flt(r.scale));
  for (int i = 0; i < kRefMaxLevels; ++i) o += fmt::format("  c.reference.levels[{}] = {};\n", i, flt(r.levels[i]));
  std::vector<std::string> services;
  for (const FirmwareFeature& f : kFirmwareFeatures)
    if (c.features & f.bit) services.push_back(f.name);
  // The port carries those of them its board can (firmware/ports/cortex-m/main.cpp).
  o += fmt::format("  c.features = 0x{:x}u;  // [firmware] features: {}\n", c.features,
                   services.empty() ? std::string("none beyond the minimum") : fmt::format("{}", fmt::join(services, ", ")));
  o += "  return c;\n}\nconstexpr RigConfig kRig = image_rig();\n";
  return o;
}

std::string capacity_part(const Rig& rig, const std::vector<RigLayer>& layers) {
  if (layers.empty())
    fail(rig, 1, "[model]", "no network shape: the image compiles one; give [[model.layer]] tables or --model FILE");
  if (rig.nd != rig.dd)
    fail(rig, 1, "nd/dd", fmt::format("an image's network shape has one history length, nd = dd ({} and {} here)",
                                      rig.nd, rig.dd));
  std::string shape = fmt::format("NetShape<{}, {}, {}, {}", rig.m(), rig.n(), rig.w(), rig.nd);
  const bool fixed_model = !(rig.firmware_features & feature::kModelUpload);
  for (const RigLayer& l : layers) shape += ", " + layer_type(l, fixed_model);
  shape += ">";
  const RigController& k = rig.controller;
  std::string o;
  o += "// The one network shape the image compiles a kernel for, and the capacity every array is sized from:\n";
  o += "// the rig's dimensions and horizons, the shape's weights and widest layer (shared/capacity.hpp).\n";
  if (fixed_model)
    o += "// No model uploads: the Dense layers' activations are the built-in model's, compiled in.\n";
  o += "using ImageShape = " + shape + ";\n";
  if (rig.firmware_size_first)
    o += "// [firmware] optimize = \"size\": no kernel of its own for the shape, the generic one (less flash,\n"
         "// more instructions a step), and the image built with NLSOFT_SIZE_FIRST (image.cmake).\n";
  o += "struct ImageCapacity {\n";
  o += fmt::format("  static constexpr int m = {}, n = {}, w = {}, nd = {};\n", rig.m(), rig.n(), rig.w(), rig.nd);
  o += fmt::format("  static constexpr int N = {}, Nc = {};\n", k.N, k.Nc);
  o += fmt::format("  static constexpr int width = ShapeNeeds<ImageShape>::width, layers = {};\n", layers.size());
  o += "  static constexpr int weights = ShapeNeeds<ImageShape>::weights;\n";
  o += rig.firmware_size_first ? "  using Shapes = ShapeList<>;\n  static constexpr bool generic = true;\n};\n"
                                : "  using Shapes = ShapeList<ImageShape>;\n  static constexpr bool generic = false;\n};\n";
  o += "using Cap = ImageCapacity;\n";
  return o;
}

namespace {

const char* shape_literal(GenericShape shape) {
  switch (shape) {
    case GenericShape::Tanh: return "GenericShape::Tanh";
    case GenericShape::Saturation: return "GenericShape::Saturation";
    case GenericShape::Power: return "GenericShape::Power";
    default: return "GenericShape::Linear";
  }
}

// A generic plant: its spec, value for value the one the console's
// simulator runs (generic_plant_spec), as a constexpr the image keeps in
// flash, and FixedGenericPlant over it (shared/plant_generic.hpp).
std::string generic_plant_part(const Rig& rig) {
  const GenericPlantSpec s = generic_plant_spec(rig);
  std::string o;
  o += "}  // namespace nlsoft::fw::cortex_m\n#include \"shared/plant_generic.hpp\"\n";
  o += "namespace nlsoft::fw::cortex_m {\n";
  o += "// The simulated plant of the HIL image ([plant] kind = \"generic\"): its constants as the console's\n";
  o += "// simulator takes them from the file (host/rig/rig_plant.cpp), kept in flash.\n";
  o += "constexpr GenericPlantSpec image_plant_spec() {\n  GenericPlantSpec s{};\n";
  o += fmt::format("  s.m = {}, s.n = {}, s.w = {};\n  s.dt = {};\n", s.m, s.n, s.w, flt(s.dt));
  o += "  // {min, max, neutral, gain, shape, knee, exponent, play, tau}\n";
  for (int i = 0; i < s.m; ++i) {
    const GenericInputSpec& in = s.input[i];
    o += fmt::format("  s.input[{}] = {{{}, {}, {}, {}, {}, {}, {}, {}, {}}};  // {}\n", i, flt(in.min), flt(in.max),
                     flt(in.neutral), flt(in.gain), shape_literal(in.shape), flt(in.knee), flt(in.exponent),
                     flt(in.play), flt(in.tau), rig.inputs[size_t(i)].name);
  }
  o += "  // {lo, hi, offset, tau}; B: row j moves output j\n";
  for (int j = 0; j < s.n; ++j) {
    const GenericOutputSpec& out = s.output[j];
    o += fmt::format("  s.output[{}] = {{{}, {}, {}, {}}};  // {}\n", j, flt(out.lo), flt(out.hi), flt(out.offset),
                     flt(out.tau), rig.outputs[size_t(j)].name);
    std::vector<std::string> row;
    for (int i = 0; i < s.m; ++i) row.push_back(fmt::format("s.B[{}][{}] = {}", j, i, flt(s.B[j][i])));
    o += fmt::format("  {};\n", fmt::join(row, ", "));
  }
  if (s.w > 0) o += "  // {offset, noise}; C: row k from the actuator states, then the outputs\n";
  for (int k = 0; k < s.w; ++k) {
    o += fmt::format("  s.sensor[{}] = {{{}, {}}};  // {}\n", k, flt(s.sensor[k].offset), flt(s.sensor[k].noise),
                     rig.sensors[size_t(k)].name);
    std::vector<std::string> row;
    for (int c = 0; c < s.m + s.n; ++c) row.push_back(fmt::format("s.C[{}][{}] = {}", k, c, flt(s.C[k][c])));
    o += fmt::format("  {};\n", fmt::join(row, ", "));
  }
  o += "  return s;\n}\ninline constexpr GenericPlantSpec kPlantSpec = image_plant_spec();\n";
  o += "using Plant = FixedGenericPlant<kPlantSpec>;\n";
  o += "static_assert(Plant::m == kRig.m && Plant::n == kRig.n && Plant::w == kRig.w, "
       "\"the plant's dimensions are the rig's\");\n";
  return o;
}

}  // namespace

std::string plant_part(const Rig& rig) {
  if (rig.plant.kind == nullptr) return "";
  if (has_generic_plant(rig)) return generic_plant_part(rig);
  const PlantEntry& p = *rig.plant.kind;
  return fmt::format("}}  // namespace nlsoft::fw::cortex_m\n#include \"{}\"\nnamespace nlsoft::fw::cortex_m {{\n"
                         "// The simulated plant of the HIL image ([plant] kind = \"{}\").\nusing Plant = {};\n"
                         "static_assert(Plant::m == kRig.m && Plant::n == kRig.n && Plant::w == kRig.w, "
                         "\"the plant's dimensions are the rig's\");\n",
                         p.header, p.name, p.type);
}

std::string pins_part(const Rig& rig, const std::string& board) {
  if (const Board* b = board_named(board); !b || b->pins != PinTable::Stm32f4) return "";
  const BoardPins* pins = find_board(board);
  if (!pins) throw CliError("no pin table for board " + board);
  namespace f4 = fw::stm32f4;
  if (rig.m() > f4::kPwmCount) {
    const RigInput& extra = rig.inputs[size_t(f4::kPwmCount)];
    fail(rig, extra.line, fmt::format("[[input]] #{}", f4::kPwmCount + 1),
         fmt::format("board {} drives {} PWM outputs ({}); this rig has {} inputs", board, f4::kPwmCount,
                     fmt::join(pins->pwm, ", "), rig.m()));
  }
  std::string o;
  o += "}  // namespace nlsoft::fw::cortex_m\n#include \"shared/board_stm32f4.hpp\"\n";
  o += "namespace nlsoft::fw::stm32f4 {\n";
  o += "// Actuator i's PWM output, a row of the board's table (shared/board_stm32f4.hpp); kNoPwm: not driven.\n";
  o += "constexpr PwmOutput kRigPwm[] = {\n";
  for (const RigInput& in : rig.inputs) {
    std::string row = "kNoPwm";
    for (size_t r = 0; r < pins->pwm.size(); ++r)
      if (pins->pwm[r] == in.pwm) row = fmt::format("kPwm[{}]", r);
    if (!in.pwm.empty() && row == "kNoPwm")
      fail(rig, in.pwm_line, "pwm", fmt::format("unknown pin '{}' on board {} (PWM pins: {})", in.pwm, board,
                                                fmt::join(pins->pwm, ", ")));
    o += fmt::format("    {},  // {}{}\n", row, in.name, in.pwm.empty() ? "" : " on " + in.pwm);
  }
  o += "};\n";
  // The board's row of an ADC1 channel (the loader checked it against the file's board; this board may differ).
  auto analogue_row = [&](int channel, int line) {
    for (size_t r = 0; r < pins->adc.size(); ++r)
      if (pins->adc[r] == channel) return r;
    fail(rig, line, "adc",
         fmt::format("unknown pin: ADC1 channel {} is not wired on board {} (channels: {})", channel, board,
                     fmt::join(pins->adc, ", ")));
  };
  auto analogue = [&](size_t row, double offset, double gain, const std::string& name, int channel) {
    return fmt::format("    {{kAnalogue[{0}].pin, kAnalogue[{0}].adc_channel, {1}, {2}}},  // {3} on ADC1_IN{4}\n", row,
                       flt(float(offset)), flt(float(gain)), name, channel);
  };
  // Rows up to the last wired sensor; the sensors after it read 0.
  size_t rows = 0;
  for (size_t i = 0; i < rig.sensors.size(); ++i)
    if (rig.sensors[i].source == SensorSource::Adc) rows = i + 1;
  o += "// Sensor i's ADC1 input and scaling (value = offset + gain * volts); kNoAnalogue and the\n";
  o += "// sensors past the table read 0.\n";
  o += fmt::format("constexpr int kRigAnalogueRows = {};\n", rows);
  o += fmt::format("constexpr AnalogueInput kRigAnalogue[{}] = {{\n", rows > 0 ? rows : 1);
  if (rows == 0) o += "    kNoAnalogue,\n";
  for (size_t i = 0; i < rows; ++i) {
    const RigSensor& s = rig.sensors[i];
    if (s.source != SensorSource::Adc) {
      o += fmt::format("    kNoAnalogue,  // {}\n", s.name);
      continue;
    }
    o += analogue(analogue_row(s.adc, s.adc_line), s.offset, s.gain, s.name, s.adc);
  }
  o += "};\n";
  // The outputs are measured only as a whole: y_true is every output or
  // none, and a model fed half a measurement would track on a mix of its
  // own predictions and readings. So the image reads them only when every
  // output is source = "adc"; with any other source it reads none.
  bool measured = true;
  for (const RigOutput& y : rig.outputs) measured = measured && y.source == OutputSource::Adc;
  o += "// Output j's ADC1 input and scaling (y = offset + gain * volts), scanned after the sensors:\n";
  o += "// rows only when every output has source = \"adc\" (the image then measures y: y_true).\n";
  o += fmt::format("constexpr int kRigOutputRows = {};\n", measured ? rig.outputs.size() : 0);
  o += fmt::format("constexpr AnalogueInput kRigOutputAnalogue[{}] = {{\n", measured ? rig.outputs.size() : 1);
  if (!measured) {
    std::vector<std::string> adc;
    for (const RigOutput& y : rig.outputs)
      if (y.source == OutputSource::Adc) adc.push_back(y.name);
    o += adc.empty() ? "    kNoAnalogue,  // no output is read on the board\n"
                     : fmt::format("    kNoAnalogue,  // {} not read: not every output is source = \"adc\"\n",
                                   fmt::join(adc, ", "));
  }
  for (size_t j = 0; measured && j < rig.outputs.size(); ++j) {
    const RigOutput& y = rig.outputs[j];
    o += analogue(analogue_row(y.adc, y.adc_line), y.offset, y.gain, y.name, y.adc);
  }
  o += "};\n}  // namespace nlsoft::fw::stm32f4\nnamespace nlsoft::fw::cortex_m {\n";
  return o;
}

std::vector<RigLayer> model_layers(const std::string& model_file, const Rig& rig) {
  model::ModelFile f;
  try {
    f = model::load_model_file(model_file);
  } catch (const std::exception& e) {
    throw CliError(fmt::format("--model {}: {}", model_file, e.what()));
  }
  const auto& s = f.shape;
  if (s.m != rig.m() || s.n != rig.n() || s.w != rig.w() || s.nd != rig.nd || s.dd != rig.dd)
    throw CliError(fmt::format("--model {}: the model is for m = {}, n = {}, w = {}, nd = {}, dd = {}; rig '{}' ({}) "
                               "has m = {}, n = {}, w = {}, nd = {}, dd = {}",
                               model_file, s.m, s.n, s.w, s.nd, s.dd, rig.name, rig.file, rig.m(), rig.n(), rig.w(),
                               rig.nd, rig.dd) +
                   // An image is built for one history length: the one train chose goes into the file.
                   (rig.lags_auto ? fmt::format(" (the rig file leaves nd to train's search: write nd = {} and dd = "
                                                "{}, the model's, into {})",
                                                s.nd, s.dd, rig.file)
                                  : std::string()));
  std::vector<RigLayer> layers;
  for (int i = 0; i < s.layer_count; ++i) {
    RigLayer l;
    l.kind = s.layer[i].kind;
    l.units = s.layer[i].out;
    l.activation = layer_kind_info(l.kind).free_activation ? model::activation_name(s.layer[i].act) : "";
    layers.push_back(l);
  }
  return layers;
}

const char* image_kinds_name(ImageKinds k) {
  switch (k) {
    case ImageKinds::Board: return "board";
    case ImageKinds::Hil: return "hil";
    case ImageKinds::Runnable: return "runnable";
    case ImageKinds::Both: break;
  }
  return "both";
}

ImageKinds parse_image_kinds(const std::string& word, const std::string& option) {
  for (ImageKinds k : {ImageKinds::Both, ImageKinds::Board, ImageKinds::Hil, ImageKinds::Runnable})
    if (word == image_kinds_name(k)) return k;
  throw CliError(fmt::format("{} {}: one of both, board, hil, runnable", option, word));
}

namespace {

// The images asked for, as the board can take them; Runnable resolved.
// What the board cannot run is refused, never left out unsaid.
ImageKinds images_for(const Rig& rig, const ImageRequest& request, bool has_plant) {
  // A chip is wired to a bus of the file's board; another board's buses are others.
  const bool chips_elsewhere = request.board != kPortableBoard && request.board != rig.board && !rig.devices.empty();
  ImageKinds k = request.images;
  if (k == ImageKinds::Runnable) k = chips_elsewhere ? ImageKinds::Hil : ImageKinds::Both;
  if (k != ImageKinds::Hil && chips_elsewhere)
    fail(rig, rig.devices[0].line, "[[device]] #1",
         fmt::format("device '{}' is on bus {} of board {}: build the image for {}, not {} (a HIL image, which "
                     "reads no chip, builds for any board)",
                     rig.devices[0].name, rig.devices[0].bus, rig.board, rig.board, request.board));
  if (k == ImageKinds::Hil && !has_plant)
    fail(rig, 1, "[plant]",
         chips_elsewhere ? fmt::format("no [plant]: board {} can run no image of this rig (its chips are on board "
                                       "{}'s buses, and a HIL image needs a simulated plant)",
                                       request.board, rig.board)
                         : std::string("no [plant]: there is no HIL image to build, only the board's"));
  return k;
}

}  // namespace

ImageSource image_source(const Rig& rig, const ImageRequest& request) {
  if (request.board != kPortableBoard)
    if (const std::string why = board_refusal(request.board, image_board_names(), "build images"); !why.empty())
      throw CliError(fmt::format("--board {}: {}", request.board, why));
  if (request.board == kPortableBoard && !rig.devices.empty())
    fail(rig, rig.devices[0].line, "[[device]] #1",
         fmt::format("a header without a board has no bus drivers for device '{}': build an image for {}",
                     rig.devices[0].name, fmt::join(image_board_names(), " or ")));
  if (const BoardPins* board = find_board(request.board); board && rig.firmware_line > 0)
    for (const FirmwareFeature& f : kFirmwareFeatures)
      if (rig.firmware_features & f.bit)
        if (const std::string why = board_lacks(*board, f); !why.empty())
          fail(rig, rig.firmware_line, "[firmware] features",
               fmt::format("'{}': {}; leave it out, or build for a board that has it", f.name, why));
  const std::vector<RigLayer> layers = !request.model_file.empty() ? model_layers(request.model_file, rig)
                                       : !request.layers.empty()   ? request.layers
                                                                   : rig.model.layers;
  const std::string plant = plant_part(rig);
  const ImageKinds kinds = images_for(rig, request, !plant.empty());
  ImageSource out;
  out.board = kinds != ImageKinds::Hil;
  out.hil = kinds != ImageKinds::Board && !plant.empty();
  // Said in the header and the build log: a board that runs the HIL image only because the chips are elsewhere.
  const std::string why = fmt::format("its chips are on board {}'s buses", rig.board);
  if (!out.board && request.images == ImageKinds::Runnable)
    out.note = fmt::format("rig '{}' on {}: the HIL image only ({})", rig.name, request.board, why);
  std::string& h = out.header;
  h += fmt::format("// Generated by nlsoft-console from the rig file {} (rig '{}', CRC-32 0x{:08x}) for board {}.\n",
                   cpp_string_literal(rig.file), rig.name, rig.hash, request.board);
  h += fmt::format("// For {}{}.\n",
                   out.board && out.hil ? "the board image and the HIL image"
                   : out.board          ? "the board image"
                                        : "the HIL image only, in which the simulated plant gives every sensor channel",
                   out.note.empty() ? "" : " (" + why + ")");
  h += "// Do not edit: `nlsoft-console firmware build --rig FILE` writes it again from the file.\n";
  h += "#pragma once\n#include <cstdint>\n\n#include \"shared/capacity.hpp\"\n#include \"shared/net_shape.hpp\"\n"
       "#include \"shared/rig_config.hpp\"\n\nnamespace nlsoft::fw::cortex_m {\n\n";
  h += rig_config_part(rig) + "\n";
  h += capacity_part(rig, layers) + "\n";
  h += plant.empty() ? "// No [plant]: no HIL image.\n" : plant;
  h += "\n" + pins_part(rig, request.board);
  if (request.board != kPortableBoard) h += "\n" + devices_part(rig);
  if (const Board* b = board_named(request.board); b && b->pins == PinTable::Stm32f4 && out.board) {
    std::vector<std::string> adc;
    for (const RigOutput& y : rig.outputs)
      if (y.source == OutputSource::Adc) adc.push_back(y.name);
    if (!adc.empty() && adc.size() < rig.outputs.size())
      out.note = fmt::format("output{} {} on ADC1 not read: the image reads the outputs only when every one has "
                             "source = \"adc\", so it measures no y (no y_true)",
                             adc.size() > 1 ? "s" : "", fmt::join(adc, ", "));
  }
  h += "\n}  // namespace nlsoft::fw::cortex_m\n";

  std::string model;
  if (!request.model_file.empty()) model = std::filesystem::absolute(request.model_file).lexically_normal().string();
  out.cmake = fmt::format(
      "# Generated with nlsoft_rig.hpp beside it; read by firmware/ports/cortex-m/images.cmake.\n"
      "set(NLSOFT_IMAGE_RIG {})\nset(NLSOFT_IMAGE_MODEL {})\nset(NLSOFT_IMAGE_BOARD {})\nset(NLSOFT_IMAGE_HIL {})\n"
      "set(NLSOFT_IMAGE_NOTE {})\nset(NLSOFT_IMAGE_DEFINITIONS {})\n",
      cmake_bracket(rig.name), cmake_bracket(model), out.board ? 1 : 0, out.hil ? 1 : 0,
      cmake_bracket(out.board ? std::string() : out.note), rig.firmware_size_first ? "NLSOFT_SIZE_FIRST=1" : "\"\"");
  return out;
}

std::string model_copy_for_image(const std::string& model_file, const std::string& dir) {
  std::ifstream in(model_file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  if (!in) throw CliError(fmt::format("--model {}: cannot read it", model_file));
  const std::string bytes = ss.str();
  const model::ModelFileParts parts =
      model::split_model_file(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  const bool cut = parts.model_size < bytes.size() && !parts.bad_trailer;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw CliError(fmt::format("cannot create {}: {}", dir, ec.message()));
  const std::string copy = dir + "/model.nlsm";
  write_text_if_changed(copy, cut ? bytes.substr(0, parts.model_size) : bytes);
  return copy;
}

void write_image_source(const ImageSource& source, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw CliError(fmt::format("cannot create {}: {}", dir, ec.message()));
  write_text_if_changed(dir + "/nlsoft_rig.hpp", source.header);
  write_text_if_changed(dir + "/image.cmake", source.cmake);
}

}  // namespace nlsoft::console
