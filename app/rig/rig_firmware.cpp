#include "app/rig/rig_firmware.hpp"

#include <fmt/format.h>

#include "app/cli_error.hpp"
#include <cstring>

#include "app/rig/board_pins.hpp"
#include "app/rig/rig_catalog.hpp"
#include "app/rig/rig_params.hpp"
#include "app/rig/rig_reference.hpp"
#include "shared/platform.hpp"
#include "shared/reference_presets.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::console {

namespace {

std::string compiled_names() {
  std::string s;
  for (int i = 0; i < kPlatformCount; ++i) s += std::string(s.empty() ? "" : ", ") + platform_name(PlatformId(i));
  return s;
}

// The first key in which `rig` is not the compiled-in preset, or "".
std::string first_difference(const Rig& rig, PlatformId id) {
  const Preset& p = preset(id);
  if (rig.m() != p.m) return "[[input]] (m)";
  if (rig.n() != p.n) return "[[output]] (n)";
  if (rig.w() != p.w) return "[[sensor]] (w)";
  if (rig.nd != p.nd || rig.dd != p.dd) return "nd/dd";
  if (float(rig.rate_hz) != p.rate_hz) return "rate_hz";
  if (rig.plant.kind != platform_name(id)) return "[plant] kind";
  Params<HostCapacity> want, got;
  if (preset_params(p, want) != Status::Ok || rig_params(rig, got) != Status::Ok) return "[controller]";
  for (int i = 0; i < p.m; ++i) {
    if (got.u_min[i] != want.u_min[i]) return fmt::format("[[input]] #{} min", i + 1);
    if (got.u_max[i] != want.u_max[i]) return fmt::format("[[input]] #{} max", i + 1);
    if (got.Lambda[i] != want.Lambda[i]) return "[controller] Lambda";
  }
  for (int i = 0; i < p.n; ++i)
    if (got.Q[i] != want.Q[i]) return "[controller] Q";
  if (got.s != want.s) return "[controller] s";
  if (got.b != want.b) return "[controller] b";
  if (got.r != want.r) return "[controller] r";
  if (got.eps != want.eps) return "[controller] eps";
  if (got.N != want.N) return "[controller] N";
  if (got.N1 != want.N1) return "[controller] N1";
  if (got.Nc != want.Nc) return "[controller] Nc";
  if (got.nr_tol != want.nr_tol) return "[controller] nr_tol";
  if (got.nr_max_iter != want.nr_max_iter) return "[controller] nr_max_iter";
  if (got.mode != want.mode) return "[controller] mode";
  if (got.feedback != want.feedback) return "[controller] feedback";
  // The images read actuator i and sensor i from row i of their pin table.
  if (const BoardPins* board = find_board(rig.board)) {
    for (size_t i = 0; i < rig.inputs.size(); ++i)
      if (!rig.inputs[i].pwm.empty() && (i >= board->pwm.size() || rig.inputs[i].pwm != board->pwm[i]))
        return fmt::format("[[input]] #{} pwm", i + 1);
    for (size_t i = 0; i < rig.sensors.size(); ++i)
      if (rig.sensors[i].source == SensorSource::Adc && (i >= board->adc.size() || rig.sensors[i].adc != board->adc[i]))
        return fmt::format("[[sensor]] #{} adc", i + 1);
  }
  if (rig.reference.kind != default_reference_kind(id)) return "[reference] kind";
  for (RefKind k : {RefKind::Infinity, RefKind::Pringle, RefKind::Diagonal, RefKind::Swirl, RefKind::Step}) {
    const RefParams a = rig_reference(rig, k), b = reference_preset(id, k);
    if (std::memcmp(&a, &b, sizeof a) != 0) return "[reference]";
  }
  return "";
}

}  // namespace

PlatformId firmware_platform(const Rig& rig, const std::string& what) {
  PlatformId id;
  if (!platform_from_name(rig.name.c_str(), &id))
    throw CliError(fmt::format(
        "{}: rig '{}' ({}) is not one of the compiled-in rigs {}; `conformance --qemu {}` tests the image built "
        "from the file, `--sim {}` serves it in the console if it has a [plant]",
        what, rig.name, rig.file, compiled_names(), rig.file, rig.file));
  const std::string diff = first_difference(rig, id);
  if (!diff.empty())
    throw CliError(fmt::format(
        "{}: rig file {} is not the compiled-in '{}' (it differs in {}): that would run its own values, not the "
        "file's; `conformance --qemu {}` tests the image built from the file",
        what, rig.file, rig.name, diff, rig.file));
  return id;
}

std::string firmware_platform_name(const std::string& arg, const std::string& what) {
  return platform_name(firmware_platform(load_rig_arg(arg), what));
}

PlatformId simulated_plant(const Rig& rig, const std::string& what) {
  PlatformId id;
  if (rig.plant.kind.empty() || !platform_from_name(rig.plant.kind.c_str(), &id))
    throw CliError(fmt::format("{}: rig '{}' ({}) has no [plant]: nothing simulates it (the simulated plants are {}, "
                               "or kind = \"generic\" with the plant's constants: docs/rig-file.md)",
                               what, rig.name, rig.file, compiled_names()));
  return id;
}

}  // namespace nlsoft::console
