#include "app/model/plant_target.hpp"

#include "app/model/error.hpp"
#include "app/model/train.hpp"
#include "shared/platform.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::pipeline {

PlantTarget platform_target(PlatformId id) {
  SimPlant plant;
  const PlantEntry* e = find_plant(platform_name(id));
  if (e == nullptr || !plant.select(e->kind)) throw PipelineError(std::string("no plant simulates ") + platform_name(id));
  PlantTarget t;
  t.name = platform_name(id);
  t.m = plant.m(), t.n = plant.n(), t.w = plant.w();
  t.nd = preset(id).nd;
  t.dd = preset(id).dd;
  t.rate_hz = double(preset(id).rate_hz);
  float lo[kMaxPlantM], hi[kMaxPlantM], ylo[kMaxPlantN], yhi[kMaxPlantN];
  plant.input_limits(lo, hi);
  plant.output_box(ylo, yhi);
  for (int i = 0; i < t.m; ++i) t.u_lo.push_back(double(lo[i])), t.u_hi.push_back(double(hi[i]));
  for (int j = 0; j < t.n; ++j) {
    t.y_rest.push_back(0.5 * (double(ylo[j]) + double(yhi[j])));
    t.y_span.push_back(double(yhi[j]) - double(ylo[j]));
    t.y_names.push_back("y" + std::to_string(j));
  }
  t.y_unit = id == PlatformId::Msd ? "m" : "mm";
  t.plant = TargetPlant::Named;
  t.kind = e->kind;
  t.measured_feedback = preset(id).feedback == Feedback::Measured;
  t.layers = default_options(id).layers;
  t.platform = uint8_t(id);
  return t;
}

PlantTarget platform_target_by_name(const std::string& name) {
  PlatformId id;
  if (!platform_from_name(name.c_str(), &id))
    throw PipelineError("unknown platform '" + name + "' (choose msd, hasel or tendon)");
  return platform_target(id);
}

}  // namespace nlsoft::pipeline
