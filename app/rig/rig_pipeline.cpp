#include "app/rig/rig_pipeline.hpp"

#include "app/model/model_store.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_plant.hpp"

namespace nlsoft::console {

using host::Rig;
using host::RigInput;
using host::RigLayer;
using host::RigOutput;
using host::generic_plant_spec;
using host::has_generic_plant;
using host::load_rig_arg;

model::PlantTarget rig_plant_target(const Rig& rig) {
  using model::TargetPlant;
  model::PlantTarget t;
  t.name = rig.name;
  t.m = rig.m(), t.n = rig.n(), t.w = rig.w(), t.nd = rig.nd, t.dd = rig.dd;
  t.lags_auto = rig.lags_auto;
  t.rate_hz = rig.rate_hz;
  t.horizon = rig.controller.N;
  for (const RigInput& in : rig.inputs) t.u_lo.push_back(in.min), t.u_hi.push_back(in.max);
  for (const RigOutput& o : rig.outputs) {
    t.y_rest.push_back(o.rest);
    t.y_span.push_back(o.span > 0 ? o.span : o.max - o.min);
    t.y_names.push_back(o.name);
  }
  t.y_unit = rig.outputs.empty() ? "" : rig.outputs[0].unit;
  t.measured_feedback = rig.controller.feedback == Feedback::Measured;
  if (has_generic_plant(rig)) {
    t.plant = TargetPlant::Generic;
    t.generic = generic_plant_spec(rig);
  } else if (rig.plant.kind != nullptr) {
    t.plant = TargetPlant::Named;
    t.kind = rig.plant.kind->kind;
  }
  // The model file names a shipped rig by its INFO number, any other 255.
  t.platform = rig.info_platform;
  for (const RigLayer& l : rig.model.layers) {
    Activation act = Activation::Linear;
    model::activation_from_name(l.activation, &act);  // the loader checked it; empty for a fixed kind's
    t.layers.push_back(model::layer_spec(l.kind, l.units, act));
  }
  return t;
}

model::PlantTarget rig_target_arg(const std::string& arg) { return rig_plant_target(load_rig_arg(arg)); }

}  // namespace nlsoft::console
