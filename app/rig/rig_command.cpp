#include "app/rig/rig_command.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "host/files/cli_error.hpp"
#include "host/files/printable.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_plant.hpp"
#include "host/rig/rig_reference.hpp"

namespace nlsoft::console {

using host::CliExit;
using host::OutputSource;
using host::Rig;
using host::RigActuator;
using host::RigController;
using host::RigDevice;
using host::RigIdentChoice;
using host::RigInput;
using host::RigLayer;
using host::RigOutput;
using host::RigPlant;
using host::RigReference;
using host::RigSensor;
using host::SensorSource;
using host::has_generic_plant;
using host::load_rig_arg;
using host::output_source_name;
using host::printable;
using host::reference_kind_name;
using host::rig_arg_help;
using host::rig_names;
using host::rig_path;
using host::sensor_source_name;

namespace {

nlohmann::json to_json(const Rig& r) {
  using nlohmann::json;
  json j;
  j["file"] = r.file;
  j["name"] = r.name;
  j["description"] = r.description;
  j["rate_hz"] = r.rate_hz;
  j["nd"] = r.nd;
  j["dd"] = r.dd;
  j["board"] = r.board;
  j["m"] = r.m();
  j["n"] = r.n();
  j["w"] = r.w();
  j["inputs"] = json::array();
  for (const RigInput& i : r.inputs)
    j["inputs"].push_back({{"name", i.name}, {"unit", i.unit}, {"min", i.min}, {"max", i.max}, {"neutral", i.neutral},
                           {"pwm", i.pwm}});
  j["outputs"] = json::array();
  for (const RigOutput& o : r.outputs) {
    json e = {{"name", o.name}, {"unit", o.unit}, {"min", o.min}, {"max", o.max}, {"span", o.span},
              {"source", output_source_name(o.source)}};
    if (o.source == OutputSource::Adc) e["adc"] = o.adc, e["gain"] = o.gain, e["offset"] = o.offset;
    j["outputs"].push_back(e);
  }
  j["sensors"] = json::array();
  for (const RigSensor& s : r.sensors) {
    json e = {{"name", s.name}, {"unit", s.unit}, {"source", sensor_source_name(s.source)}};
    if (s.source == SensorSource::Adc) e["adc"] = s.adc, e["gain"] = s.gain, e["offset"] = s.offset;
    if (s.source == SensorSource::Device)
      e["device"] = r.devices[size_t(s.device)].name,
      e["channel"] = r.devices[size_t(s.device)].chip->channel_names[s.channel], e["gain"] = s.gain,
      e["offset"] = s.offset;
    j["sensors"].push_back(e);
  }
  j["devices"] = json::array();
  for (const RigDevice& d : r.devices) {
    json e = {{"name", d.name}, {"chip", d.chip->name}, {"bus", d.bus}, {"clock_hz", d.clock_hz}};
    if (d.kind == BusKind::I2c) {
      e["address"] = d.address;
    } else if (d.kind == BusKind::Serial) {
      e.erase("clock_hz");
      e["id"] = d.address;
      e["baud"] = d.clock_hz;
      e["on_fault"] = d.release_on_fault ? "release" : "hold";
    } else {
      e["cs"] = d.cs;
    }
    if (d.chip->range_count) e["range"] = d.range;
    if (d.chip->rate_count) e["rate_hz"] = d.rate_hz;
    j["devices"].push_back(e);
  }
  const RigController& c = r.controller;
  j["controller"] = {{"Q", c.Q},     {"Lambda", c.Lambda}, {"s", c.s},         {"b", c.b},
                     {"r", c.r},     {"N", c.N},           {"N1", c.N1},       {"Nc", c.Nc},
                     {"eps", c.eps}, {"nr_tol", c.nr_tol}, {"nr_max_iter", c.nr_max_iter},
                     {"mode", c.mode == DerivMode::Fd ? "fd" : "exact"},
                     {"feedback", c.feedback == Feedback::Measured ? "measured" : "predicted"}};
  json layers = json::array();
  for (const RigLayer& L : r.model.layers) {
    json e = {{"kind", layer_kind_info(L.kind).name}, {"units", L.units}};
    if (!L.activation.empty()) e["activation"] = L.activation;
    layers.push_back(e);
  }
  j["model"] = {{"file", r.model.file}, {"layers", layers}};
  j["plant"] = r.plant.kind == nullptr ? json(nullptr) : json(r.plant.kind->name);
  if (has_generic_plant(r)) {
    const RigPlant& p = r.plant;
    json acts = json::array();
    for (const RigActuator& a : p.actuators)
      acts.push_back({{"gain", a.gain}, {"shape", generic_shape_name(a.shape)}, {"knee", a.knee}, {"exponent", a.exponent},
                      {"play", a.play}, {"tau", a.tau}});
    j["generic_plant"] = {{"actuators", acts},           {"coupling", p.coupling},
                          {"output_offset", p.output_offset}, {"output_tau", p.output_tau},
                          {"sensor_map", p.sensor_map},       {"sensor_offset", p.sensor_offset},
                          {"sensor_noise", p.sensor_noise}};
  }
  const RigReference& g = r.reference;
  j["reference"] = {{"kind", reference_kind_name(g.kind)},
                    {"centre", g.centre},
                    {"amplitude", g.amplitude},
                    {"pringle_amplitude", g.pringle_amplitude},
                    {"swirl_centre", g.swirl_centre},
                    {"swirl_scale", g.swirl_scale},
                    {"step_levels", g.step_levels}};
  // Only what the file sets: ident's own defaults are not the rig's.
  auto choice = [](const RigIdentChoice& set) {
    json e = json::object();
    if (set.amplitude > 0) e["amplitude"] = set.amplitude;
    if (set.band_hi > 0) e["band_hz"] = {set.band_lo, set.band_hi};
    return e;
  };
  json ident = choice(r.ident.all);
  for (uint8_t i = 0; i < kExcitationSignalCount; ++i)
    if (const json e = choice(r.ident.signal[i]); !e.empty()) ident[kExcitationSignalNames[i]] = e;
  j["ident"] = ident;
  j["pid"] = !r.pid.given ? json(nullptr)
                          : json{{"kp", r.pid.kp},
                                 {"ki", r.pid.ki},
                                 {"kd", r.pid.kd},
                                 {"output_scale", r.pid.output_scale},
                                 {"d_filter_tau", r.pid.d_filter_tau}};
  return j;
}

std::string unit(const std::string& u) { return u.empty() ? "" : " " + printable(u); }

// The file's text is checked by the loader (no control characters); it is
// shown escaped all the same, as everything a file brings to a terminal.
void print_summary(const Rig& r) {
  fmt::print("{}: rig '{}'{}\n", printable(r.file), printable(r.name),
             r.description.empty() ? "" : " - " + printable(r.description));
  fmt::print("  {} Hz, nd = dd = {}, board {}\n", r.rate_hz, r.nd, r.board);
  fmt::print("  m = {} inputs:\n", r.m());
  for (const RigInput& i : r.inputs)
    fmt::print("    {:<10} [{}, {}]{}, neutral {}{}\n", i.name, i.min, i.max, unit(i.unit), i.neutral,
               !i.servo.empty() ? fmt::format(", servo {} (goal {} + {} per{})", i.servo, i.goal_at_neutral,
                                              i.goal_per_unit, i.unit.empty() ? " unit" : unit(i.unit))
               : i.pwm.empty()  ? ", not wired"
                                : ", PWM " + i.pwm);
  fmt::print("  n = {} outputs:\n", r.n());
  for (const RigOutput& o : r.outputs)
    fmt::print("    {:<10} [{}, {}]{}, span {}, {}\n", o.name, o.min, o.max, unit(o.unit), o.span,
               o.source == OutputSource::Adc ? fmt::format("ADC1 channel {}", o.adc)
               : o.source == OutputSource::External ? std::string("measured outside the board")
                                                    : std::string("predicted only"));
  int adc = 0, chips = 0;
  std::string unwired;
  for (const RigSensor& s : r.sensors) {
    if (s.source == SensorSource::Adc) ++adc;
    else if (s.source == SensorSource::Device) ++chips;
    else unwired += (unwired.empty() ? "" : ", ") + s.name;
  }
  fmt::print("  w = {} sensors: {} on ADC1{}{}\n", r.w(), adc, chips ? fmt::format(", {} from chips", chips) : "",
             unwired.empty() ? "" : ", not wired: " + unwired);
  for (const RigDevice& d : r.devices)
    fmt::print("    device {:<10} {} on {} {}{}{}\n", d.name, d.chip->name, d.bus,
               d.kind == BusKind::I2c      ? fmt::format("at 0x{:02x}", d.address)
               : d.kind == BusKind::Serial ? fmt::format("id {} at {} baud, {} on a fault", d.address, d.clock_hz,
                                                         d.release_on_fault ? "released" : "held")
                                           : "chip select " + d.cs,
               d.chip->range_count ? fmt::format(", {} {}", d.range, d.chip->range_unit) : "",
               d.chip->rate_count ? fmt::format(", {} Hz", d.rate_hz) : "");
  const RigController& c = r.controller;
  fmt::print("  controller: N {}, Nc {}, s {}, b {}, r {}, eps {}, {}, feedback {}\n", c.N, c.Nc, c.s, c.b, c.r, c.eps,
             c.mode == DerivMode::Fd ? "fd" : "exact", c.feedback == Feedback::Measured ? "measured" : "predicted");
  std::string layers;
  for (const RigLayer& L : r.model.layers)
    layers += (layers.empty() ? "" : " -> ") + std::string(layer_kind_info(L.kind).name) + " " + std::to_string(L.units) +
              (L.activation.empty() ? "" : " " + L.activation);
  fmt::print("  model: {}{}\n", r.model.file.empty() ? "none named" : printable(r.model.file),
             layers.empty() ? "" : " (" + layers + ")");
  std::string shapes;
  for (const RigActuator& a : r.plant.actuators) shapes += (shapes.empty() ? "" : ", ") + std::string(generic_shape_name(a.shape));
  fmt::print("  simulated plant: {}{}\n", r.plant.kind == nullptr ? "none" : r.plant.kind->name,
             has_generic_plant(r) ? " (actuators " + shapes + ")" : "");
  fmt::print("  default reference: {}\n", reference_kind_name(r.reference.kind));
  std::string ident;
  for (uint8_t i = 0; i < kExcitationSignalCount; ++i) {
    const RigIdentChoice set = r.ident.for_signal(ExcitationSignal(i));
    if (set.amplitude <= 0 && set.band_hi <= 0) continue;
    ident += fmt::format("{}{}", ident.empty() ? "" : "; ", kExcitationSignalNames[i]);
    if (set.band_hi > 0) ident += fmt::format(" band {:g}:{:g} Hz", set.band_lo, set.band_hi);
    if (set.amplitude > 0) ident += fmt::format(" amplitude {:g}", set.amplitude);
  }
  if (!ident.empty()) fmt::print("  ident defaults: {}\n", ident);
  if (r.pid.given)
    fmt::print("  PID baseline: kp {:g}, ki {:g}, kd {:g}, output scale {:g}, derivative filter {:g} s\n", r.pid.kp,
               r.pid.ki, r.pid.kd, r.pid.output_scale, r.pid.d_filter_tau);
}

}  // namespace

void add_rig_command(CLI::App& app, LiveDeviceCheck check_live) {
  CLI::App* rig = app.add_subcommand("rig", "Rig files (docs/rig-file.md): check one, list the shipped ones");
  rig->require_subcommand(1);

  struct CheckOptions {
    std::string rig, port;
    unsigned baud = 115200;
    bool json = false;
  };
  auto check_opts = std::make_shared<CheckOptions>();
  CLI::App* check = rig->add_subcommand(
      "check", "Load and validate a rig file; print what it describes (exit 2 and file:line: key on a fault)");
  check->add_option("rig", check_opts->rig, "rig file, or a shipped rig's name: " + rig_arg_help())->required();
  check->add_flag("--json", check_opts->json, "the loaded rig as JSON on stdout");
  check->add_option("PORT", check_opts->port,
                    "a firmware's serial port: also say how each of the rig's sensor chips answers there "
                    "(exit 1 when one is not ok)");
  check->add_option("--baud", check_opts->baud, "the port's baud rate")->capture_default_str();
  check->callback([check_opts, check_live] {
    const Rig r = load_rig_arg(check_opts->rig);
    if (check_opts->json)
      fmt::print("{}\n", to_json(r).dump(2));
    else
      print_summary(r);
    if (check_opts->port.empty()) return;
    std::fflush(stdout);
    if (const int rc = check_live(r, check_opts->port, check_opts->baud); rc != 0) throw CliExit{rc};
  });

  auto list_json = std::make_shared<bool>(false);
  CLI::App* list = rig->add_subcommand("list", "The shipped rigs (the names --rig, --sim and --platform take)");
  list->add_flag("--json", *list_json, "as JSON: [{name, file}]");
  list->callback([list_json] {
    nlohmann::json j = nlohmann::json::array();
    for (const std::string& n : rig_names()) {
      const std::string path = rig_path(n);
      if (*list_json)
        j.push_back({{"name", n}, {"file", path}});
      else
        fmt::print("{:<10} {}\n", n, path);
    }
    if (*list_json) fmt::print("{}\n", j.dump(2));
  });
}

}  // namespace nlsoft::console
