#include "app/rig/rig_plant.hpp"

#include "app/rig/rig_firmware.hpp"


namespace nlsoft::console {

namespace {

GenericShape shape_of(const std::string& name) {
  if (name == "tanh") return GenericShape::Tanh;
  if (name == "saturation") return GenericShape::Saturation;
  if (name == "power") return GenericShape::Power;
  return GenericShape::Linear;
}

}  // namespace

bool has_generic_plant(const Rig& rig) { return rig.plant.kind == "generic"; }

GenericPlantSpec generic_plant_spec(const Rig& rig) {
  const RigPlant& p = rig.plant;
  GenericPlantSpec s{};
  s.m = uint8_t(rig.m()), s.n = uint8_t(rig.n()), s.w = uint8_t(rig.w());
  s.dt = float(1.0 / rig.rate_hz);
  for (size_t i = 0; i < rig.inputs.size() && i < p.actuators.size(); ++i) {
    const RigInput& in = rig.inputs[i];
    const RigActuator& a = p.actuators[i];
    s.input[i] = {float(in.min), float(in.max), float(in.neutral), float(a.gain), shape_of(a.shape),
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

void require_simulated_plant(const Rig& rig, const std::string& what) {
  if (!has_generic_plant(rig)) simulated_plant(rig, what);
}

}  // namespace nlsoft::console
