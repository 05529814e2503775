#include "host/rig/rig_plant.hpp"

#include <fmt/format.h>

#include "host/files/cli_error.hpp"

namespace nlsoft::host {

bool has_generic_plant(const Rig& rig) { return rig.plant.kind != nullptr && rig.plant.kind->kind == PlantKind::Generic; }

GenericPlantSpec generic_plant_spec(const Rig& rig) {
  const RigPlant& p = rig.plant;
  GenericPlantSpec s{};
  s.m = uint8_t(rig.m()), s.n = uint8_t(rig.n()), s.w = uint8_t(rig.w());
  s.dt = float(1.0 / rig.rate_hz);
  for (size_t i = 0; i < rig.inputs.size() && i < p.actuators.size(); ++i) {
    const RigInput& in = rig.inputs[i];
    const RigActuator& a = p.actuators[i];
    s.input[i] = {float(in.min), float(in.max), float(in.neutral), float(a.gain), a.shape,
                  float(a.knee), float(a.exponent), float(a.play), float(a.tau)};
  }
  for (size_t j = 0; j < rig.outputs.size(); ++j) {
    s.output[j] = {float(rig.outputs[j].min), float(rig.outputs[j].max), float(p.output_offset[j]),
                   float(p.output_tau[j])};
    for (size_t i = 0; i < rig.inputs.size(); ++i) s.B[j][i] = float(p.coupling[j][i]);
  }
  for (size_t k = 0; k < rig.sensors.size(); ++k) {
    s.sensor[k] = {float(p.sensor_offset[k]), float(p.sensor_noise[k])};
    for (size_t c = 0; c < p.sensor_map[k].size(); ++c) s.C[k][c] = float(p.sensor_map[k][c]);
  }
  return s;
}

const PlantEntry& simulated_plant(const Rig& rig, const std::string& what) {
  if (rig.plant.kind == nullptr) {
    std::string names;
    for (const PlantEntry& e : kPlantRegistry) names += std::string(names.empty() ? "" : ", ") + e.name;
    throw CliError(fmt::format("{}: rig '{}' ({}) has no [plant]: nothing simulates it (give it [plant] kind = one of "
                               "{}; generic with the plant's constants: docs/rig-file.md)",
                               what, rig.name, rig.file, names));
  }
  return *rig.plant.kind;
}

}  // namespace nlsoft::host
