#pragma once
// The connected firmware's parameters as a search's ParamSource: names
// resolved against its list, the values in force read from it.
#include "app/live/live_console.hpp"
#include "app/tune/search_space.hpp"

namespace nlsoft::console {

class LiveParamSource final : public ParamSource {
 public:
  explicit LiveParamSource(LiveConsole& console) : console_(console) {}
  std::pair<ParamInfo, int> resolve(const std::string& name) override { return console_.params().resolve(name); }
  std::vector<double> in_force(const ParamInfo& info) override { return console_.params().get(info.name).second; }

 private:
  LiveConsole& console_;
};

}  // namespace nlsoft::console
