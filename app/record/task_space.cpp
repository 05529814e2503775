#include "app/record/task_space.hpp"

namespace nlsoft::console {

std::vector<double> task_space(const std::string& platform) {
  if (platform == "hasel") return {23.0, 20.2, 19.2};
  if (platform == "tendon") return {40.4, 28.3, 35.0};
  if (platform == "msd") return {2.0};
  return {};
}

}  // namespace nlsoft::console
