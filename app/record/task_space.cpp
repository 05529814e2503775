#include "app/record/task_space.hpp"

#include <algorithm>

#include "host/rig/rig_catalog.hpp"

namespace nlsoft::console {

std::vector<double> task_space(const std::string& platform) {
  // The spans of the rig file of that name among the installed rigs.
  const std::vector<std::string> names = rig_names();
  if (std::find(names.begin(), names.end(), platform) == names.end()) return {};
  std::vector<double> spans;
  for (const RigOutput& o : load_rig_arg(platform).outputs) spans.push_back(o.span);
  return spans;
}

}  // namespace nlsoft::console
