#include "app/record/task_space.hpp"

#include <algorithm>

#include "host/rig/rig_catalog.hpp"

namespace nlsoft::console {

using host::Rig;
using host::RigOutput;
using host::load_rig_arg;
using host::rig_names;

std::vector<double> task_space(const std::string& platform) {
  // The spans of the rig file of that name among the installed rigs.
  const std::vector<std::string> names = rig_names();
  if (std::find(names.begin(), names.end(), platform) == names.end()) return {};
  std::vector<double> spans;
  for (const RigOutput& o : load_rig_arg(platform).outputs) spans.push_back(o.span);
  return spans;
}

RigColumns rig_columns(const std::string& platform, int n, int m, int w) {
  RigColumns c;
  const auto names = rig_names();
  if (std::find(names.begin(), names.end(), platform) == names.end()) return c;
  try {
    const Rig rig = load_rig_arg(platform);
    if (int(rig.outputs.size()) == n && int(rig.inputs.size()) == m) {
      for (const auto& o : rig.outputs) c.output_names.push_back(o.name), c.output_units.push_back(o.unit);
      for (const auto& i : rig.inputs) c.input_names.push_back(i.name), c.input_units.push_back(i.unit);
      if (int(rig.sensors.size()) == w)
        for (const auto& l : rig.sensors) c.sensor_names.push_back(l.name), c.sensor_units.push_back(l.unit);
    }
  } catch (const std::exception&) {
    // an unreadable rig file: no names
  }
  return c;
}

std::string axis_label(const std::vector<std::string>& names, const std::vector<std::string>& units, size_t i,
                       const std::string& fallback) {
  const std::string name = i < names.size() && !names[i].empty() ? names[i] : fallback;
  return i < units.size() && !units[i].empty() ? name + " (" + units[i] + ")" : name;
}

}  // namespace nlsoft::console
